// three.js plays sprung's glTF animation of a tearing cloth as the frame
// files have it, in headless Chromium:
//   1. GLTFLoader loads DIR/animation.glb and a WebGLRenderer draws it
//      (its morph targets within what a shader takes: no error);
//   2. for every frame of DIR/expected.json (its time, the f32 the file
//      holds, and the .vtu frame's triangle count) the AnimationMixer is
//      set to that time and the triangles with an area are counted, their
//      corners read back through three's morph targets
//      (Mesh.getVertexPosition) in world space (a hidden span of frames
//      is scaled to 0): the count is the .vtu's, before the tear and
//      after it.
//
// usage: node gltf.mjs DIR
// DIR holds animation.glb and expected.json (crates/sprung-cli/tests/gltf.rs
// writes them). Prints one line of JSON with what it measured; exits 1 on
// a failure.

import path from "node:path";
import { fileURLToPath } from "node:url";
import { fail, launch, newPage, serve } from "./common.mjs";

const [dataDir] = process.argv.slice(2);
if (!dataDir) {
  console.error("usage: node gltf.mjs DIR");
  process.exit(2);
}
const here = path.dirname(fileURLToPath(import.meta.url));
const three = path.join(here, "node_modules/three");

/** The page: three from node_modules through an import map. */
const PAGE = `<!doctype html>
<html><body><canvas id="view" width="320" height="240"></canvas>
<script type="importmap">{"imports": {"three": "/three/build/three.module.js",
  "three/addons/": "/three/examples/jsm/"}}</script>
<script type="module">
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

/** The number of triangles of the meshes under \`root\` with an area now,
 *  their corners morphed as three morphs them, in world space. */
function trianglesWithArea(root) {
  root.updateMatrixWorld(true);
  const [a, b, c] = [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()];
  const triangle = new THREE.Triangle(a, b, c);
  let count = 0;
  root.traverse((mesh) => {
    if (!mesh.isMesh) return;
    const index = mesh.geometry.index;
    const corners = index ? index.count : mesh.geometry.attributes.position.count;
    const corner = (k) => (index ? index.getX(k) : k);
    for (let k = 0; k + 2 < corners; k += 3) {
      for (const [j, v] of [a, b, c].entries()) {
        mesh.getVertexPosition(corner(k + j), v).applyMatrix4(mesh.matrixWorld);
      }
      if (triangle.getArea() > 0) count++;
    }
  });
  return count;
}

window.check = async () => {
  const expected = await (await fetch("/data/expected.json")).json();
  const gltf = await new GLTFLoader().loadAsync("/data/animation.glb");
  const scene = new THREE.Scene();
  scene.add(gltf.scene);
  const mixer = new THREE.AnimationMixer(gltf.scene);
  const action = mixer.clipAction(gltf.animations[0]);
  // Played once and held at the end (a repeating clip wraps its last time to 0).
  action.setLoop(THREE.LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
  let targets = 0;
  gltf.scene.traverse((m) => { if (m.isMesh) targets = Math.max(targets, m.morphTargetInfluences?.length ?? 0); });
  const renderer = new THREE.WebGLRenderer({ canvas: document.getElementById("view") });
  const camera = new THREE.PerspectiveCamera(40, 4 / 3, 0.1, 100);
  camera.position.set(0.75, 1.6, 3.0);
  camera.lookAt(0.75, 1.45, 0.0);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x444444, 2));
  const counts = [];
  for (const frame of expected.frames) {
    // From the start each time (a finished clip held at its end stays
    // paused, and setTime would leave it at 0).
    action.reset();
    mixer.setTime(frame.time);
    counts.push({ time: frame.time, expected: frame.triangles, shown: trianglesWithArea(gltf.scene) });
    renderer.render(scene, camera);
  }
  const gl = renderer.getContext();
  return { counts, targets, glError: gl.getError(), programs: renderer.info.programs.length,
    meshes: gltf.scene.children.length };
};
</script></body></html>`;

async function main() {
  const server = await serve(three, { "/three/": three, "/data/": dataDir });
  const port = server.address().port;
  const browser = await launch();
  const problems = [];
  try {
    const page = await newPage(browser, problems);
    await page.route(`http://127.0.0.1:${port}/`, (route) =>
      route.fulfill({ contentType: "text/html", body: PAGE }));
    await page.goto(`http://127.0.0.1:${port}/`);
    await page.waitForFunction(() => typeof window.check === "function", null, { timeout: 30_000 })
      .catch(() => fail(`the page did not load three: ${problems.join("; ") || "no error in the console"}`));
    const result = await page.evaluate(() => window.check());
    if (problems.length) fail(problems.join("; "));
    if (result.glError !== 0) fail(`WebGL error ${result.glError} after drawing`);
    if (result.programs === 0) fail("three compiled no shader program");
    const wrong = result.counts.filter((c) => c.shown !== c.expected);
    if (wrong.length) fail(`triangles with an area against the .vtu's: ${JSON.stringify(wrong)}`);
    const whole = Math.max(...result.counts.map((c) => c.expected));
    const before = result.counts.filter((c) => c.expected === whole).length;
    const after = result.counts.length - before;
    if (!before || !after) fail(`no frame before or after the tear: ${JSON.stringify(result.counts)}`);
    const torn = result.counts[result.counts.length - 1];
    console.log(JSON.stringify({ frames: result.counts.length, before, after, whole,
      last: torn, targetsPerMesh: result.targets, programs: result.programs }));
  } finally {
    await browser.close();
    server.close();
  }
}

main().catch((error) => {
  console.error(error.stack || String(error));
  process.exit(1);
});
