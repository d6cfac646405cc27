// The web viewer steps on the browser's WebGPU, in headless Chromium (its
// WebGPU runs on SwiftShader, on the CPU, with --enable-unsafe-webgpu):
//   1. a cloth in free fall from a scene with `device = "gpu"` steps on the
//      GPU (its count of GPU steps grows, the page shows no message), and
//      its centre of mass is where symplectic Euler puts a falling body
//      after the steps its clock shows;
//   2. `?device=gpu#flag` steps the flag demo in wind on the GPU, with no
//      error, and the picture is not blank;
//   3. a Chromium that offers no WebGPU adapter steps the same scene on the
//      engine, and the page says why.
//
// usage: node gpu.mjs WEB_DIR SCENES_DIR [SHOT.png]
// SCENES_DIR holds fall.toml (the Rust test writes it), served at /user/.
// Prints one line of JSON with what it measured; exits 1 on a failure.

import fs from "node:fs";
import { call, checkBuilt, fail, launch, newPage, pixelStats, serve, waitForFrames } from "./common.mjs";

const [webDir, scenesDir, shotPath] = process.argv.slice(2);
if (!webDir || !scenesDir) {
  console.error("usage: node gpu.mjs WEB_DIR SCENES_DIR [SHOT.png]");
  process.exit(2);
}

// fall.toml: symplectic Euler, dt = 1 ms, g = 9.81 m/s², no drag; the
// cloth starts at rest with its springs at their rest lengths.
const DT = 1e-3, G = 9.81;

/** The page's message box: its text, "" when hidden. */
function messageText(page) {
  return page.evaluate(() => {
    const box = document.getElementById("message");
    return box.hidden ? "" : box.textContent;
  });
}

/** The clock, the GPU's steps and the particles' mean height, read between
 *  two frames (one evaluation: no frame runs in it). */
function snapshot(page) {
  return page.evaluate(() => {
    const count = wasm_exports.sprung_particle_count();
    let sum = 0;
    for (let i = 0; i < count; i++) sum += wasm_exports.sprung_particle(i, 1);
    return {
      time: wasm_exports.sprung_time(), gpuSteps: wasm_exports.sprung_gpu_steps(),
      count, meanY: sum / count,
    };
  });
}

/** Open `fall.toml`, wait for the GPU to arrive (with `gpu`: the engine
 *  steps until it does), then for `steps` more steps; the state then. */
async function openFall(page, origin, steps, gpu) {
  await page.goto(`${origin}/#scene=/user/fall.toml`);
  await page.waitForFunction(
    () => typeof wasm_exports !== "undefined" && wasm_exports.sprung_frames
      && wasm_exports.sprung_demo() === -1 && wasm_exports.sprung_particle_count() === 64,
    null, { timeout: 90_000 },
  ).catch(async () => fail(`fall.toml did not open; the page says: ${await messageText(page)}`));
  if (gpu) {
    await page.waitForFunction(() => wasm_exports.sprung_gpu_steps() > 0, null, { timeout: 60_000 })
      .catch(async () => fail(`fall.toml: no step on the GPU; the page says: ${await messageText(page)}`));
  }
  const start = await snapshot(page);
  await page.waitForFunction((t) => wasm_exports.sprung_time() >= t, start.time + steps * DT, { timeout: 120_000 })
    .catch(() => fail(`fall.toml: the clock did not reach ${steps} steps`));
  return start;
}

async function main() {
  const root = checkBuilt(webDir);
  const server = await serve(root, { "/user/": scenesDir });
  const origin = `http://127.0.0.1:${server.address().port}`;
  const report = {};
  try {
    // 1 and 2, with WebGPU.
    let browser = await launch(["--enable-unsafe-webgpu"]);
    try {
      const problems = [];
      const page = await newPage(browser, problems);
      const start = await openFall(page, origin, 300, true);
      const end = await snapshot(page);
      const message = await messageText(page);
      if (message) fail(`fall.toml on the GPU: the page says: ${message}`);
      // Every step since the GPU arrived went to it (it counts those read
      // back, as the clock does).
      const landed = Math.round((end.time - start.time) / DT);
      if (end.gpuSteps - start.gpuSteps !== landed) {
        fail(`fall.toml: ${end.gpuSteps - start.gpuSteps} of ${landed} steps on the GPU`);
      }
      // Symplectic Euler from rest: v_n = -g n h, y_n = y_0 - g h² n(n+1)/2.
      // The springs' forces cancel in pairs (each end gathers the same
      // f32 force with the sign turned), so the mean falls so. The clock
      // holds the steps landed (a compensated sum of dt: n to 1e-9).
      const n = Math.round(end.time / DT);
      if (Math.abs(end.time - n * DT) > 1e-9) fail(`the clock ${end.time} s is not a whole number of steps`);
      const y0 = start.meanY + G * DT * DT * Math.round(start.time / DT) * (Math.round(start.time / DT) + 1) / 2;
      const expected = y0 - G * DT * DT * n * (n + 1) / 2;
      // f32 positions: each step rounds a height of at most ~2 m to
      // within 1.2e-7 m, at most n·1.2e-7 = 6e-5 m after 500 steps if the
      // roundings all lean one way; one step too many or too few moves
      // the mean by g h n ≈ 5e-3 m, a hundred times more.
      const off = Math.abs(end.meanY - expected);
      if (off > 6e-5 * Math.max(1, n / 500)) {
        fail(`fall.toml on the GPU: mean height ${end.meanY} m after ${n} steps, free fall says ${expected} m (off by ${off})`);
      }
      report.fall = { steps: n, gpuSteps: end.gpuSteps, meanY: end.meanY, expected, off };

      await page.goto(`${origin}/?device=gpu#flag`);
      await waitForFrames(page, 5, problems);
      await page.waitForFunction(() => wasm_exports.sprung_gpu_steps() > 200 && wasm_exports.sprung_demo() >= 0,
        null, { timeout: 120_000 })
        .catch(async () => fail(`?device=gpu#flag: the GPU took ${await call(page, "sprung_gpu_steps")} steps; the page says: ${await messageText(page)}`));
      if (await call(page, "sprung_error")) fail(`the flag on the GPU: ${await messageText(page)}`);
      const png = await page.screenshot();
      if (shotPath) fs.writeFileSync(shotPath, png);
      const stats = await pixelStats(page, png);
      if (stats.colours < 50 || stats.differing < 0.05) {
        fail(`the flag's screenshot looks blank: ${stats.colours} colours, ${(100 * stats.differing).toFixed(1)}% unlike the background`);
      }
      report.flag = { gpuSteps: await call(page, "sprung_gpu_steps"), time: await call(page, "sprung_time"), ...stats };
      if (problems.length) fail(problems.join("; "));
    } finally {
      await browser.close();
    }

    // 3, without a WebGPU adapter: the engine takes the steps.
    browser = await launch();
    try {
      const problems = [];
      const page = await newPage(browser, problems);
      await openFall(page, origin, 100, false);
      // The browser's answer (no adapter) comes a few frames after the ask.
      await page.waitForFunction(() => !document.getElementById("message").hidden, null, { timeout: 30_000 })
        .catch(() => fail("without WebGPU the page said nothing"));
      const end = await snapshot(page);
      const message = await messageText(page);
      if (end.gpuSteps !== 0) fail(`without WebGPU, ${end.gpuSteps} steps on the GPU`);
      if (!message.includes("no WebGPU")) fail(`without WebGPU the page says: "${message}"`);
      report.noWebGpu = { time: end.time, message };
      if (problems.length) fail(problems.join("; "));
    } finally {
      await browser.close();
    }
    console.log(JSON.stringify(report));
  } finally {
    server.close();
  }
}

main().catch((error) => {
  console.error(`web viewer GPU test failed: ${error.message}`);
  process.exit(1);
});
