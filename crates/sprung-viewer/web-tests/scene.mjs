// The web viewer opens the user's own scenes, in headless Chromium:
//   1. a scene file (and a mesh it uses) given through the "Open scene"
//      file picker runs: the simulation's own state (the wasm exports)
//      has the scene's particle count, time advances and a particle falls;
//   2. `#scene=URL` loads a scene served beside the page, its mesh
//      fetched relative to it;
//   3. a broken scene shows an error on the page with its file and line,
//      in one box (the page's: the canvas draws none), once;
//   4. a served scene with an error, fixed on the disk, is fetched again
//      by R and runs;
//   5. a served scene naming a mesh that is not there is an error on its
//      line (not one of sprung's built-in meshes of the same name);
//   6. an unknown `#name` shows a message listing the demos.
//
// usage: node scene.mjs WEB_DIR SCENES_DIR
// SCENES_DIR holds mine.toml, its mesh box.asc, broken.toml, fix.toml
// (broken on line 6 until this script mends it) and nomesh.toml (the Rust
// test writes them); it is served at /user/. Prints one line of JSON with
// what it measured; exits 1 on a failure.

import fs from "node:fs";
import path from "node:path";
import { call, checkBuilt, fail, launch, newPage, serve, waitForFrames } from "./common.mjs";

const [webDir, scenesDir] = process.argv.slice(2);
if (!webDir || !scenesDir) {
  console.error("usage: node scene.mjs WEB_DIR SCENES_DIR");
  process.exit(2);
}

/** The page's message box: its text, "" when hidden. */
function messageText(page) {
  return page.evaluate(() => {
    const box = document.getElementById("message");
    return box.hidden ? "" : box.textContent;
  });
}

/** The mean height of the first `count` particles (m). */
async function meanHeight(page, count) {
  let sum = 0;
  for (let i = 0; i < count; i++) sum += await call(page, "sprung_particle", i, 1);
  return sum / count;
}

/** Wait until the viewer runs a scene of `count` particles that is not a
 *  demo, with no error, and check that it moves: time advances and the
 *  bodies' mean height falls (nothing holds them up). */
async function runsScene(page, count, what) {
  await page.waitForFunction(
    (n) => wasm_exports.sprung_demo() === -1 && wasm_exports.sprung_particle_count() === n,
    count, { timeout: 30_000 },
  ).catch(async () => fail(`${what}: the scene did not open; the page says: ${await messageText(page)}`));
  if (await call(page, "sprung_error")) fail(`${what}: the viewer shows an error: ${await messageText(page)}`);
  const [t0, y0] = [await call(page, "sprung_time"), await meanHeight(page, count)];
  await page.waitForFunction((t) => wasm_exports.sprung_time() > t + 0.2, t0, { timeout: 30_000 })
    .catch(() => fail(`${what}: simulated time did not advance`));
  const [t1, y1] = [await call(page, "sprung_time"), await meanHeight(page, count)];
  if (!(y1 < y0)) fail(`${what}: the bodies did not fall (mean height ${y0} then ${y1} m)`);
  return { time: [t0, t1], y: [y0, y1] };
}

async function main() {
  const root = checkBuilt(webDir);
  const server = await serve(root, { "/user/": scenesDir });
  const port = server.address().port;
  const browser = await launch();
  const problems = [];
  const result = {};
  try {
    const page = await newPage(browser, problems);
    await page.goto(`http://127.0.0.1:${port}/#ball2d`);
    await waitForFrames(page, 5, problems);
    const file = (name) => ({
      name, mimeType: "application/octet-stream", buffer: fs.readFileSync(path.join(scenesDir, name)),
    });
    // The scene has a rope of 4 particles and the cube mesh's 8.
    await page.setInputFiles("#scene-file", [file("mine.toml"), file("box.asc")]);
    result.picker = await runsScene(page, 12, "through the picker");

    // A broken scene: an error naming the file and the line.
    await page.setInputFiles("#scene-file", [file("broken.toml")]);
    await page.waitForFunction(() => wasm_exports.sprung_error() === 1, null, { timeout: 30_000 })
      .catch(() => fail("the broken scene shows no error"));
    await page.waitForFunction(
      () => !document.getElementById("message").hidden, null, { timeout: 10_000 },
    ).catch(() => fail("the broken scene's error is not on the page"));
    const broken = await messageText(page);
    if (!/broken\.toml:6:/.test(broken)) fail(`the error does not give broken.toml and line 6: ${broken}`);
    result.broken = broken;

    // The same scene served beside the page, with its mesh.
    await page.goto(`http://127.0.0.1:${port}/#scene=user/mine.toml`);
    await waitForFrames(page, 5, problems);
    result.url = await runsScene(page, 12, "#scene=user/mine.toml");

    // A served scene with an error on line 6, then mended on the disk (5
    // free particles, which fall): R fetches it again and it runs.
    await page.goto(`http://127.0.0.1:${port}/#scene=user/fix.toml`);
    await waitForFrames(page, 5, problems);
    await page.waitForFunction(() => wasm_exports.sprung_error() === 1, null, { timeout: 30_000 })
      .catch(() => fail("fix.toml shows no error"));
    await page.waitForFunction(
      () => !document.getElementById("message").hidden, null, { timeout: 10_000 },
    ).catch(() => fail("fix.toml's error is not on the page"));
    const unfixed = await messageText(page);
    if (unfixed.split("fix.toml:6:").length !== 2) fail(`fix.toml's error is not shown once: ${unfixed}`);
    if (!unfixed.includes("press R to load it again")) fail(`no hint to press R: ${unfixed}`);
    fs.writeFileSync(path.join(scenesDir, "fix.toml"),
      "[sim]\ndt = 1e-3\nduration = 100.0\n\n[[body]]\nname = \"pair\"\n" +
      "particles = [[0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.5, 1.5, 0.0], [0.0, 2.0, 0.0], [1.0, 2.0, 0.0]]\n" +
      "springs = [[0, 1], [1, 2], [2, 3], [3, 4]]\nmass = 0.1\n");
    await page.keyboard.press("r");
    result.fixed = await runsScene(page, 5, "fix.toml read again with R");
    if (await messageText(page) !== "") fail(`a message stays after the fix: ${await messageText(page)}`);

    // A served scene naming a mesh the server does not have.
    await page.goto(`http://127.0.0.1:${port}/#scene=user/nomesh.toml`);
    await waitForFrames(page, 5, problems);
    await page.waitForFunction(() => wasm_exports.sprung_error() === 1, null, { timeout: 30_000 })
      .catch(() => fail("a missing mesh shows no error"));
    await page.waitForFunction(
      () => !document.getElementById("message").hidden, null, { timeout: 10_000 },
    ).catch(() => fail("the missing mesh's error is not on the page"));
    const nomesh = await messageText(page);
    if (!/nomesh\.toml:6:/.test(nomesh) || !nomesh.includes("meshes/horse.obj")) {
      fail(`the missing mesh's error does not give nomesh.toml, line 6 and the mesh: ${nomesh}`);
    }
    result.nomesh = nomesh;

    // An unknown demo.
    await page.goto(`http://127.0.0.1:${port}/#nosuch`);
    await waitForFrames(page, 5, problems);
    await page.waitForFunction(
      () => !document.getElementById("message").hidden, null, { timeout: 10_000 },
    ).catch(() => fail("#nosuch shows no message"));
    const unknown = await messageText(page);
    if (!unknown.includes("nosuch") || !unknown.includes("ball2d") || !unknown.includes("flag")) {
      fail(`the message for #nosuch does not list the demos: ${unknown}`);
    }
    result.unknown = unknown;
    // The viewer logs the broken scene's error to the console too: expected.
    // So do the other scenes with an error, and the browser the missing
    // mesh's 404.
    const expected = ["cannot load the scene: broken.toml", "cannot load the scene: fix.toml",
      "cannot load the scene: nomesh.toml", "404"];
    const unexpected = problems.filter((p) => !expected.some((e) => p.includes(e)));
    if (unexpected.length) fail(unexpected.join("; "));
    console.log(JSON.stringify(result));
  } finally {
    await browser.close();
    server.close();
  }
}

main().catch((error) => {
  console.error(`web viewer scene test failed: ${error.message}`);
  process.exit(1);
});
