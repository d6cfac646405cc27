// The web viewer in headless Chromium: serve the built page from 127.0.0.1,
// load it, wait for frames, drag a particle with the mouse and check from
// the simulation's own state (the wasm module's exports) that it followed
// the cursor, then check that a screenshot of the page is not blank.
//
// usage: node drag.mjs WEB_DIR [SCREENSHOT.png]
// WEB_DIR is what scripts/build-web.sh builds (target/web). Chromium is
// $CHROMIUM, else /usr/bin/chromium (scripts/test.sh installs Debian's).
// Prints one line of JSON with what it measured; exits 1 on a failure.

import fs from "node:fs";
import { call, checkBuilt, fail, launch, newPage, pixelStats, serve, waitForFrames } from "./common.mjs";

const [webDir, shotPath] = process.argv.slice(2);
if (!webDir) {
  console.error("usage: node drag.mjs WEB_DIR [SCREENSHOT.png]");
  process.exit(2);
}

async function particle(page, i) {
  const p = [];
  for (const axis of [0, 1, 2]) p.push(await call(page, "sprung_particle", i, axis));
  return p;
}

async function cursor(page) {
  const p = [];
  for (const axis of [0, 1, 2]) p.push(await call(page, "sprung_cursor", axis));
  return p;
}

const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

async function main() {
  const root = checkBuilt(webDir);
  const server = await serve(root);
  const port = server.address().port;
  const browser = await launch();
  const problems = [];
  try {
    const page = await newPage(browser, problems);
    await page.goto(`http://127.0.0.1:${port}/#ball2d`);
    await waitForFrames(page, 10, problems);
    const demo = await call(page, "sprung_demo");
    if (demo !== 0) fail(`the page shows demo ${demo}, not ball2d (0)`);
    if (await call(page, "sprung_error")) fail("the page shows an error");

    // Let the ball land (it is dropped at t = 0), then pause with the
    // keyboard (Space) so that the particle stays under the cursor while
    // the mouse goes down on it: the top particle of the gas-filled ball
    // (body 0: particles 0 to 16).
    await page.waitForFunction(() => wasm_exports.sprung_time() > 2.0, null, { timeout: 90_000 })
      .catch(() => fail("the simulation did not reach t = 2 s within 90 s"));
    await page.keyboard.press("Space");
    await page.waitForTimeout(300);
    const pausedAt = await call(page, "sprung_time");
    await page.waitForTimeout(300);
    if ((await call(page, "sprung_time")) !== pausedAt) fail("Space did not pause the simulation");
    let top = 0;
    for (let i = 1; i < 17; i++) {
      if ((await particle(page, i))[1] > (await particle(page, top))[1]) top = i;
    }
    const box = await page.locator("#glcanvas").boundingBox();
    const sx = box.x + await call(page, "sprung_particle_screen", top, 0);
    const sy = box.y + await call(page, "sprung_particle_screen", top, 1);
    await page.mouse.move(sx, sy);
    await page.waitForTimeout(100);
    await page.mouse.down();
    await page.waitForFunction(() => wasm_exports.sprung_grabbed() >= 0, null, { timeout: 10_000 })
      .catch(() => fail(`pressing the mouse at (${sx}, ${sy}) on particle ${top} grabbed nothing`));
    await page.keyboard.press("Space");
    const grabbed = await call(page, "sprung_grabbed");
    const start = await particle(page, grabbed);
    const [dx, dy] = [220, -160];
    for (let k = 1; k <= 20; k++) {
      await page.mouse.move(sx + (dx * k) / 20, sy + (dy * k) / 20);
      await page.waitForTimeout(30);
    }
    // Hold still while the spring pulls the ball up to the cursor.
    await page.waitForTimeout(2500);
    const held = await particle(page, grabbed);
    const target = await cursor(page);
    const still = await call(page, "sprung_grabbed");
    const time = await call(page, "sprung_time");
    await page.mouse.up();
    await page.waitForFunction(() => wasm_exports.sprung_grabbed() === -1, null, { timeout: 10_000 })
      .catch(() => fail("releasing the mouse did not let go of the particle"));

    const moved = distance(held, start);
    const off = distance(held, target);
    if (still !== grabbed) fail(`the grab moved from particle ${grabbed} to ${still}`);
    if (moved < 0.8) fail(`particle ${grabbed} moved ${moved.toFixed(3)} m: it did not follow the cursor`);
    if (off > 0.2) fail(`particle ${grabbed} is ${off.toFixed(3)} m from the cursor's point ${target}`);

    const png = await page.screenshot();
    if (shotPath) fs.writeFileSync(shotPath, png);
    const stats = await pixelStats(page, png);
    if (stats.colours < 50 || stats.differing < 0.05) {
      fail(`the screenshot looks blank: ${stats.colours} colours, ${(100 * stats.differing).toFixed(1)}% unlike the background`);
    }
    const frames = await call(page, "sprung_frames");
    const fps = await call(page, "sprung_fps");
    if (problems.length) fail(problems.join("; "));
    console.log(JSON.stringify({ grabbed, start, held, target, moved, off, time, frames, fps, ...stats }));
  } finally {
    await browser.close();
    server.close();
  }
}

main().catch((error) => {
  console.error(`web viewer test failed: ${error.message}`);
  process.exit(1);
});
