// tools/web/drive.mjs - opens the web page (tools/web/index.html) in headless Chromium through
// puppeteer-core (installed by tools/web_install.sh), waits until the globe has loaded its tiles,
// takes a screenshot, samples Cesium's terrain heights and reports every error it saw
// (docs/web.md; tests/test_web_cesium.sh runs it).
//
//   node tools/web/drive.mjs --url URL --out PNG [--size WxH] [--points FILE] [--json FILE]
//                            [--timeout S] [--chromium PATH]
//
//   --url      the page with its parameters (index.html?tiles=...&camera-geo=...)
//   --out      the screenshot (PNG) after the tiles loaded
//   --size     the viewport, default 960x540
//   --points   a JSON list of [lon, lat]: the heights Cesium samples there
//              (sampleTerrainMostDetailed) go into the report, with the tile level of each
//   --json     the report: load_ms, webgl (the renderer), errors (the page's collected Cesium
//              tile, imagery and render errors, script errors, console errors), failed_requests,
//              http_errors (status >= 400), external_requests (anything not from 127.0.0.1 or
//              localhost, nor data:/blob:), samples
//   --timeout  seconds for the tiles to load (default 90)
//   --chromium the browser (default $TP_CHROMIUM, else chromium on PATH)
//
// Exit 0 when the page loaded with no error of any kind; 1 after a line per problem (the report
// is written all the same when the page could be opened); 2 on a usage error.
import { createRequire } from "node:module";
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";

const ME = "terrapatch: tools/web/drive.mjs";

function die(msg, code = 1) {
  process.stderr.write(`${ME}: ${msg}\n`);
  process.exit(code);
}

function parseArgs(argv) {
  const a = { size: "960x540", timeout: 90, chromium: process.env.TP_CHROMIUM || "" };
  const names = new Set(["url", "out", "size", "points", "json", "timeout", "chromium"]);
  for (let i = 0; i < argv.length; i++) {
    const m = /^--([a-z]+)(?:=(.*))?$/.exec(argv[i]);
    if (!m || !names.has(m[1])) die(`unknown argument '${argv[i]}' (--url, --out, --size, --points, --json, --timeout, --chromium)`, 2);
    const v = m[2] !== undefined ? m[2] : argv[++i];
    if (v === undefined) die(`missing value for --${m[1]}`, 2);
    a[m[1]] = v;
  }
  if (!a.url || !a.out) die("--url and --out are required", 2);
  const s = /^([0-9]+)x([0-9]+)$/.exec(a.size);
  if (!s || +s[1] < 16 || +s[2] < 16) die(`--size: expected WxH, got '${a.size}'`, 2);
  a.width = +s[1];
  a.height = +s[2];
  a.timeout = Number(a.timeout);
  if (!(a.timeout > 0)) die("--timeout: seconds > 0", 2);
  return a;
}

function findChromium(given) {
  if (given) return given;
  for (const name of ["chromium", "chromium-browser"]) {
    try {
      return execFileSync("sh", ["-c", `command -v ${name}`], { encoding: "utf8" }).trim();
    } catch {
      /* next */
    }
  }
  die(`chromium not found on PATH (${process.env.PATH}): install Debian's chromium (tools/deps.sh does) or set TP_CHROMIUM`);
}

function loadPuppeteer() {
  const cache = process.env.XDG_CACHE_HOME || path.join(os.homedir(), ".cache");
  const dir = process.env.TP_WEB_DIR || path.join(cache, "terrapatch", "web");
  try {
    return createRequire(path.join(dir, "package.json"))("puppeteer-core");
  } catch {
    die(`puppeteer-core is not in ${dir}: run tools/web_install.sh`);
  }
}

function isLocal(url) {
  if (/^(data|blob):/.test(url)) return true;
  try {
    const h = new URL(url).hostname;
    return h === "127.0.0.1" || h === "localhost" || h === "[::1]";
  } catch {
    return false;
  }
}

async function main() {
  const a = parseArgs(process.argv.slice(2));
  const points = a.points ? JSON.parse(fs.readFileSync(a.points, "utf8")) : [];
  const puppeteer = loadPuppeteer();
  const report = { url: a.url, errors: [], failed_requests: [], http_errors: [], external_requests: [], samples: [] };
  const args = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist",
                "--disable-dev-shm-usage", "--no-first-run", "--no-default-browser-check",
                `--window-size=${a.width},${a.height}`];
  if (process.getuid && process.getuid() === 0) args.push("--no-sandbox"); // root: no user namespace sandbox
  const browser = await puppeteer.launch({
    executablePath: findChromium(a.chromium), headless: true, args,
    defaultViewport: { width: a.width, height: a.height }, protocolTimeout: (a.timeout + 60) * 1000,
  });
  let page;
  try {
    page = await browser.newPage();
    page.on("console", (m) => { if (m.type() === "error") report.errors.push(`console: ${m.text()}`); });
    page.on("pageerror", (e) => report.errors.push(`page: ${e.message.split("\n")[0]}`));
    page.on("request", (r) => { if (!isLocal(r.url())) report.external_requests.push(r.url()); });
    page.on("requestfailed", (r) =>
      report.failed_requests.push(`${r.url()}: ${r.failure() ? r.failure().errorText : "failed"}`));
    page.on("response", (r) => { if (r.status() >= 400) report.http_errors.push(`${r.url()}: HTTP ${r.status()}`); });
    const t0 = Date.now();
    await page.goto(a.url, { waitUntil: "load", timeout: a.timeout * 1000 });
    await page.waitForFunction(() => Boolean(window.tpWeb && window.tpWeb.ready), { timeout: 30000 });
    // the page's own error (already in its errors) ends the run without waiting for tiles
    const failed = await page.evaluate(() =>
      window.tpWeb.ready.then(() => "", (e) => String((e && e.message) || e)));
    report.ready_ms = Date.now() - t0;
    if (failed) throw new Error(`the page did not start: ${failed}`);
    report.webgl = await page.evaluate(() => {
      const gl = window.tpWeb.viewer.scene.context._gl;
      const ext = gl.getExtension("WEBGL_debug_renderer_info");
      const name = ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
      return `${window.tpWeb.viewer.scene.context.webgl2 ? "WebGL 2" : "WebGL 1"}, ${name}`;
    });
    await page.evaluate((ms) => window.tpWeb.waitLoaded(ms), a.timeout * 1000);
    report.load_ms = Date.now() - t0;
    await page.screenshot({ path: a.out, type: "png" });
    if (points.length) report.samples = await page.evaluate((p) => window.tpWeb.sample(p), points);
    report.errors.push(...(await page.evaluate(() => window.tpWeb.errors)));
  } catch (e) {
    report.errors.push(`driver: ${e.message.split("\n")[0]}`);
    try {
      report.errors.push(...(await page.evaluate(() => (window.tpWeb ? window.tpWeb.errors : []))));
    } catch {
      /* the page is gone */
    }
  } finally {
    await browser.close();
  }
  if (a.json) fs.writeFileSync(a.json, JSON.stringify(report, null, 1) + "\n");
  report.errors = [...new Set(report.errors)];
  const problems = [...report.errors, ...report.failed_requests, ...report.http_errors,
                    ...report.external_requests.map((u) => `external request: ${u}`)];
  for (const p of problems) process.stderr.write(`${ME}: ${p}\n`);
  process.exit(problems.length ? 1 : 0);
}

main().catch((e) => die(e.message.split("\n")[0]));
