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
  for (const file of ["index.html", "gl.js", "sprung-viewer.js", "sprung-viewer.wasm"]) {
    if (!fs.existsSync(path.join(root, file))) fail(`${root}/${file} is missing: run scripts/build-web.sh`);
  }
  return root;
}

/** Headless Chromium ($CHROMIUM, else Debian's), with software WebGL;
 *  `extra` switches after the usual ones (`--enable-unsafe-webgpu`: its
 *  WebGPU, on SwiftShader where there is no GPU). */
export function launch(extra = []) {
  return chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    headless: true,
    args: [
      "--headless", "--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
      "--disable-quic", "--no-first-run", ...extra,
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

/** Distinct colours and the share of pixels unlike the top-right corner's, in the page. */
export function pixelStats(page, png) {
  return page.evaluate(async (base64) => {
    const image = new Image();
    image.src = "data:image/png;base64," + base64;
    await image.decode();
    const canvas = document.createElement("canvas");
    canvas.width = image.width;
    canvas.height = image.height;
    const context = canvas.getContext("2d");
    context.drawImage(image, 0, 0);
    const data = context.getImageData(0, 0, canvas.width, canvas.height).data;
    const corner = 4 * (canvas.width - 1);
    const colours = new Set();
    let differing = 0;
    for (let i = 0; i < data.length; i += 4) {
      colours.add((data[i] >> 3) << 10 | (data[i + 1] >> 3) << 5 | data[i + 2] >> 3);
      const d = Math.abs(data[i] - data[corner]) + Math.abs(data[i + 1] - data[corner + 1])
        + Math.abs(data[i + 2] - data[corner + 2]);
      if (d > 24) differing++;
    }
    return { colours: colours.size, differing: differing / (data.length / 4) };
  }, png.toString("base64"));
}
