// What the browser tests of the web viewer share: a static file server,
// Chromium launched headless as this machine allows, and calls into the
// viewer's wasm exports.

import fs from "node:fs";
import http from "node:http";
import path from "node:path";
import { chromium } from "playwright-core";

const TYPES = {
  ".html": "text/html", ".js": "text/javascript", ".wasm": "application/wasm",
  ".toml": "text/plain",
};

export function fail(message) {
  throw new Error(message);
}

/** Serve `root` on 127.0.0.1 (a free port); `mounts` maps a URL prefix
 *  (`/user/`) to another folder. Resolves to the server. */
export function serve(root, mounts = {}) {
  const server = http.createServer((request, response) => {
    const name = decodeURIComponent(new URL(request.url, "http://x").pathname);
    let base = path.resolve(root);
    let rest = name === "/" ? "index.html" : name;
    for (const [prefix, folder] of Object.entries(mounts)) {
      if (name.startsWith(prefix)) {
        base = path.resolve(folder);
        rest = name.slice(prefix.length);
      }
    }
    const file = path.join(base, path.normalize(rest));
    if (!file.startsWith(base) || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
      response.writeHead(404).end();
      return;
    }
    const type = TYPES[path.extname(file)] ?? "application/octet-stream";
    response.writeHead(200, { "Content-Type": type });
    fs.createReadStream(file).pipe(response);
  });
  return new Promise((resolve) => server.listen(0, "127.0.0.1", () => resolve(server)));
}

/** The built page in `webDir`, checked. */
export function checkBuilt(webDir) {
  const root = path.resolve(webDir);
  for (const file of ["index.html", "gl.js", "sprung-viewer.wasm"]) {
    if (!fs.existsSync(path.join(root, file))) fail(`${root}/${file} is missing: run scripts/build-web.sh`);
  }
  return root;
}

/** Headless Chromium ($CHROMIUM, else Debian's), with software WebGL. */
export function launch() {
  return chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    headless: true,
    args: [
      "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--disable-quic", "--no-first-run",
    ],
  });
}

/** A page that records its errors in `problems`. */
export async function newPage(browser, problems) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on("pageerror", (error) => problems.push(`page error: ${error.message}`));
  page.on("console", (message) => {
    if (message.type() === "error") problems.push(`console error: ${message.text()}`);
  });
  return page;
}

/** Wait until the viewer has drawn `frames` frames. */
export async function waitForFrames(page, frames, problems) {
  await page.waitForFunction(
    (n) => typeof wasm_exports !== "undefined" && wasm_exports.sprung_frames && wasm_exports.sprung_frames() > n,
    frames, { timeout: 90_000 },
  ).catch(() => fail(`no frames within 90 s; ${problems.join("; ") || "no error in the console"}`));
}

/** Call an export of the wasm module. */
export function call(page, name, ...args) {
  return page.evaluate(([name, args]) => wasm_exports[name](...args), [name, args]);
}
