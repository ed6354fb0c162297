// Opens the browser build in Debian's headless Chromium and reports what it showed, as one JSON
// object on stdout: node tests/web/open.mjs DIR QUERY SCREENSHOT [FRAMES]
//
// DIR is scripts/web's folder, served here over HTTP on 127.0.0.1 (a free port; browsers refuse
// WebAssembly from file:// pages). QUERY is the page's query string (`scene=seed`). The script
// waits until the canvas says FRAMES frames were drawn (default 60), presses Space (pause) and
// reads the tick before and after ten more frames, presses P (the window's screenshot, which a
// page offers as a download, saved beside SCREENSHOT as NAME-key-p.png), writes a screenshot of
// the page to SCREENSHOT, and prints { frames, tick, tickAtPause, tickAfterPause, scene,
// adapter, replay, download, error, console }. With `replay=` in QUERY it first waits for the
// replay's verdict (the canvas's data-replay). Without it, V before the pause records a few
// frames, which a page offers as a download (saved as NAME-recorded.vrec, named in
// `recording`). With PICK=FILE in the environment, FILE is then picked in the page's file input
// and its replay's verdict reported as `picked`. With KEYS="KeyC KeyA ..." those keys are
// pressed ten frames apart and the canvas's lanes, aims and tick reported as `keys`. A page
// that shows an error instead (`#volley-error`) is reported with that text as soon as it
// appears.
import { createServer } from "node:http";
import { readFile } from "node:fs/promises";
import { extname, join, normalize } from "node:path";
import { chromium } from "playwright-core";

const [dir, query, screenshot, framesArg] = process.argv.slice(2);
if (!dir || query === undefined || !screenshot) {
  console.error("usage: node open.mjs DIR QUERY SCREENSHOT [FRAMES]");
  process.exit(2);
}
const wantFrames = Number(framesArg ?? 60);
const types = { ".html": "text/html", ".js": "text/javascript", ".wasm": "application/wasm" };

const server = createServer(async (req, res) => {
  const path = normalize(decodeURIComponent(new URL(req.url, "http://x").pathname));
  const file = join(dir, path.endsWith("/") ? path + "index.html" : path);
  try {
    const body = await readFile(file);
    res.writeHead(200, { "content-type": types[extname(file)] ?? "application/octet-stream" });
    res.end(body);
  } catch {
    res.writeHead(404);
    res.end();
  }
});
await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
const url = `http://127.0.0.1:${server.address().port}/?${query}`;

// Headless Chromium as root, with the flags that give it WebGPU on SwiftShader (the machines
// here have no GPU) and keep it off the network.
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
  args: [
    "--no-sandbox",
    "--enable-unsafe-webgpu",
    "--use-angle=swiftshader",
    "--enable-features=Vulkan",
    // Without it the WebGPU canvas is never composited: the page (and the canvas read from
    // JavaScript) stays empty though the frames are drawn.
    "--use-vulkan=swiftshader",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-quic",
    "--no-first-run",
    ...(process.env.CHROMIUM_FLAGS ?? "").split(" ").filter(Boolean),
  ],
});
const report = { console: [] };
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on("console", (m) => report.console.push(`${m.type()}: ${m.text()}`));
  page.on("pageerror", (e) => report.console.push(`pageerror: ${e.message}`));
  await page.goto(url);
  const canvasData = () =>
    page.evaluate(() => {
      const c = document.querySelector("canvas");
      const e = document.getElementById("volley-error");
      return {
        frames: Number(c?.dataset.frames ?? 0),
        tick: Number(c?.dataset.tick ?? 0),
        scene: c?.dataset.scene ?? null,
        adapter: c?.dataset.adapter ?? null,
        replay: c?.dataset.replay ?? null,
        error: e ? e.textContent : null,
      };
    });
  await page.waitForFunction(
    (n) => {
      const c = document.querySelector("canvas");
      return document.getElementById("volley-error") || Number(c?.dataset.frames ?? 0) >= n;
    },
    wantFrames,
    { timeout: 240_000, polling: 200 },
  );
  if (query.includes("replay=")) {
    // A replay: wait for its verdict (verified to the end, or parted).
    await page.waitForFunction(
      () => {
        const c = document.querySelector("canvas");
        const v = c?.dataset.replay ?? "";
        return document.getElementById("volley-error") || /^verified|parts from/.test(v);
      },
      null,
      { timeout: 240_000, polling: 200 },
    );
  }
  Object.assign(report, await canvasData());
  const waitFrames = (n) =>
    page.waitForFunction(
      (m) => Number(document.querySelector("canvas").dataset.frames) >= m,
      n,
      { timeout: 120_000, polling: 100 },
    );
  const downloadOf = async (key, file) => {
    const download = page.waitForEvent("download", { timeout: 60_000 });
    await page.keyboard.press(key);
    const d = await download.catch(() => null);
    if (d === null) return null;
    await d.saveAs(file);
    return d.suggestedFilename();
  };
  if (report.error === null && !query.includes("replay=")) {
    // V starts a recording and V again ends it: a page offers it as a download.
    await page.locator("canvas").focus();
    await page.keyboard.press("KeyV");
    await waitFrames(report.frames + 15);
    report.recording = await downloadOf("KeyV", screenshot.replace(/\.png$/, "-recorded.vrec"));
  }
  if (report.error === null && process.env.PICK) {
    // A recording picked in the page's file input replays (and verifies) in the window.
    await page.setInputFiles("#volley-open", process.env.PICK);
    await page.waitForFunction(
      () => /^verified|parts from/.test(document.querySelector("canvas").dataset.replay ?? ""),
      null,
      { timeout: 240_000, polling: 200 },
    );
    report.picked = (await canvasData()).replay;
  }
  if (report.error === null && process.env.KEYS) {
    // KEYS="KeyC KeyA": each key pressed in turn, ten frames apart, then the lanes and aims
    // the canvas reports.
    await page.locator("canvas").focus();
    for (const key of process.env.KEYS.split(" ").filter(Boolean)) {
      await page.keyboard.press(key);
      await waitFrames((await canvasData()).frames + 10);
    }
    await waitFrames((await canvasData()).frames + 30);
    report.keys = await page.evaluate(() => {
      const c = document.querySelector("canvas");
      return {
        lanes: c.dataset.lanes ?? "",
        aims: Number(c.dataset.aims ?? 0),
        tick: Number(c.dataset.tick),
      };
    });
  }
  if (report.error === null) {
    // A key press reaches the window: Space pauses, so the tick stands still after it.
    await page.locator("canvas").focus();
    await page.keyboard.press("Space");
    const pausedAt = await canvasData();
    const frames = pausedAt.frames;
    await page.waitForFunction(
      (n) => Number(document.querySelector("canvas").dataset.frames) >= n + 10,
      frames,
      { timeout: 120_000, polling: 100 },
    );
    const later = await canvasData();
    report.tickAtPause = pausedAt.tick;
    report.tickAfterPause = later.tick;
    report.framesAfterPause = later.frames;
    // P: the window's own screenshot, the frame drawn again offscreen and read back, which a
    // page offers as a download. (Chromium's page screenshot does not capture a WebGPU canvas
    // on SwiftShader here: it comes back white.)
    const download = page.waitForEvent("download", { timeout: 60_000 });
    await page.keyboard.press("KeyP");
    const fileOrNull = await download.catch(async (e) => {
      report.downloadError = `${e.message.split("\n")[0]}; page: ${JSON.stringify(await canvasData())}`;
      return null;
    });
    if (fileOrNull !== null) {
      report.download = fileOrNull.suggestedFilename();
      await fileOrNull.saveAs(screenshot.replace(/\.png$/, "-key-p.png"));
    }
  }
  await page.screenshot({ path: screenshot });
} finally {
  await browser.close();
  server.close();
}
console.log(JSON.stringify(report));
