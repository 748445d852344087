// The run viewer in a real browser: Debian's chromium driven by playwright-core.
// Run by ctest (test "browser_viewer") with PLUMETRACE_CLI set; PLUMETRACE_CHROMIUM overrides
// the browser (default /usr/bin/chromium). scripts/setup.sh installs both.
import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { pathToFileURL } from "node:url";
import { inflateSync } from "node:zlib";

const cli = process.env.PLUMETRACE_CLI;
const browserPath = process.env.PLUMETRACE_CHROMIUM || "/usr/bin/chromium";

// ---- a PNG decoder (8-bit RGB or RGBA, not interlaced: what chromium's screenshots are)
function decodePng(buffer) {
  let pos = 8;
  let width = 0, height = 0, channels = 0;
  const idat = [];
  while (pos < buffer.length) {
    const length = buffer.readUInt32BE(pos);
    const type = buffer.toString("ascii", pos + 4, pos + 8);
    const body = buffer.subarray(pos + 8, pos + 8 + length);
    if (type === "IHDR") {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      assert.equal(body[8], 8, "8-bit PNG");
      assert.equal(body[12], 0, "not interlaced");
      channels = { 2: 3, 6: 4 }[body[9]];
      assert.ok(channels, `colour type ${body[9]}`);
    } else if (type === "IDAT") {
      idat.push(body);
    }
    pos += 12 + length;
  }
  const raw = inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const out = Buffer.alloc(width * height * 3);
  const prev = Buffer.alloc(stride), line = Buffer.alloc(stride);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const src = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let i = 0; i < stride; ++i) {
      const a = i >= channels ? line[i - channels] : 0;
      const b = prev[i];
      const c = i >= channels ? prev[i - channels] : 0;
      let p = 0;
      if (filter === 1) p = a;
      else if (filter === 2) p = b;
      else if (filter === 3) p = (a + b) >> 1;
      else if (filter === 4) {
        const pa = Math.abs(b - c), pb = Math.abs(a - c), pc = Math.abs(a + b - 2 * c);
        p = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      line[i] = (src[i] + p) & 255;
    }
    for (let x = 0; x < width; ++x) {
      for (let k = 0; k < 3; ++k) out[(y * width + x) * 3 + k] = line[x * channels + k];
    }
    line.copy(prev);
  }
  return { width, height, pixel: (x, y) => [...out.subarray((y * width + x) * 3, (y * width + x) * 3 + 3)] };
}

const hex = (h) => [1, 3, 5].map((i) => parseInt(h.slice(i, i + 2), 16));
const near = (p, q, tol) => Math.abs(p[0] - q[0]) <= tol && Math.abs(p[1] - q[1]) <= tol && Math.abs(p[2] - q[2]) <= tol;

// pixels in a box (device pixels) that satisfy a predicate
function count(img, box, pred) {
  let n = 0;
  const x0 = Math.max(0, Math.floor(box.x0)), x1 = Math.min(img.width, Math.ceil(box.x1));
  const y0 = Math.max(0, Math.floor(box.y0)), y1 = Math.min(img.height, Math.ceil(box.y1));
  for (let y = y0; y < y1; ++y) for (let x = x0; x < x1; ++x) if (pred(img.pixel(x, y))) ++n;
  return n;
}
const bluish = (p) => p[2] > p[0] + 25 && p[2] > p[1] + 5;

// ---- the runs and the browser
let dir, browser, chromium;
const errors = [];
const offline = [];

function plumetrace(...args) {
  return execFileSync(cli, args, { cwd: dir, encoding: "utf8" });
}

before(async () => {
  assert.ok(cli && existsSync(cli), "PLUMETRACE_CLI must name the plumetrace binary");
  assert.ok(existsSync(browserPath), `no browser at ${browserPath}: run scripts/setup.sh`);
  try {
    ({ chromium } = await import("playwright-core"));
  } catch (e) {
    assert.fail(`playwright-core is missing (${e.message}): run scripts/setup.sh`);
  }
  dir = mkdtempSync(join(tmpdir(), "plumetrace-viewer-"));
  // a run with every layer: casting on the default scenario (plume, casts, wind samples)
  plumetrace("run", "--trace", "run.json", "--snapshot-interval", "0.25");
  plumetrace("view", "run.json", "-o", "run.html");
  plumetrace("view", "run.json", "-o", "run.svg");
  // a long run (37 500 steps): a tight spiral that never smells odor until the timeout
  plumetrace("run", "--algorithm", "surge-spiral", "--set", "surge_spiral.d_gap=0.02",
             "--set", "odor.threshold=1e15", "--view", "long.html");
  browser = await chromium.launch({
    executablePath: browserPath,
    args: ["--no-sandbox", "--disable-background-networking", "--disable-component-update",
           "--disable-default-apps", "--disable-sync", "--no-first-run"],
  });
});

after(async () => {
  if (browser) await browser.close();
  if (dir) rmSync(dir, { recursive: true, force: true });
});

async function open(file) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 720 } });
  page.on("console", (m) => { if (m.type() === "error") errors.push(`${file}: ${m.text()}`); });
  page.on("pageerror", (e) => errors.push(`${file}: ${e.message}`));
  // the page must not reach the network: anything but file: is recorded and refused
  await page.route("**/*", (route) => {
    const url = route.request().url();
    if (url.startsWith("file:")) return route.continue();
    offline.push(url);
    return route.abort();
  });
  await page.goto(pathToFileURL(join(dir, file)).href);
  return page;
}

const viewer = (page, expr) => page.evaluate(`window.plumetraceViewer.${expr}`);

test("the page loads from disk without console errors or network requests", async () => {
  const page = await open("run.html");
  assert.ok((await viewer(page, "frames")) > 1000);
  assert.equal(await page.locator("#p-state").textContent(), "upwind");
  // the outcome line says what the trace's result says
  const result = JSON.parse(readFileSync(join(dir, "run.json"), "utf8")).result;
  assert.ok((await page.locator("#outcome").textContent())
    .includes(`${result.outcome} at ${result.time_s.toFixed(2)} s`));
  await page.close();
  assert.deepEqual(errors, []);
  assert.deepEqual(offline, []);
});

test("scrubbing the timeline moves the robot and the clock", async () => {
  const page = await open("run.html");
  const n = await viewer(page, "frames");
  const start = await viewer(page, "robotOnScreen()");
  const box = await page.locator("#timeline").boundingBox();
  // a real click on the slider at 60 % of its length
  await page.mouse.click(box.x + 0.6 * box.width, box.y + box.height / 2);
  const frame = await viewer(page, "frame()");
  assert.ok(Math.abs(frame - 0.6 * (n - 1)) < 0.03 * n, `frame ${frame} of ${n}`);
  const moved = await viewer(page, "robotOnScreen()");
  assert.ok(Math.hypot(moved.x - start.x, moved.y - start.y) > 50, "the robot moved on screen");
  assert.match(await page.locator("#clock").textContent(), new RegExp(`frame ${frame + 1}/${n}`));
  // single steps, with the keyboard and the buttons
  await page.keyboard.press("ArrowRight");
  assert.equal(await viewer(page, "frame()"), frame + 1);
  await page.locator("#back").click();
  await page.locator("#back").click();
  assert.equal(await viewer(page, "frame()"), frame - 1);
  // play advances, pause stops
  await page.locator("#play").click();
  await page.waitForFunction((f) => window.plumetraceViewer.frame() > f + 10, frame);
  await page.locator("#play").click();
  assert.equal(await viewer(page, "playing()"), false);
  await page.close();
  assert.deepEqual(errors, []);
});

test("zoom and pan change the scale and the offset", async () => {
  const page = await open("run.html");
  const a = await viewer(page, "toScreen(1, 0)"), b = await viewer(page, "toScreen(2, 0)");
  await page.locator("#zoom-in").click();
  const a2 = await viewer(page, "toScreen(1, 0)"), b2 = await viewer(page, "toScreen(2, 0)");
  assert.ok(Math.abs((b2.x - a2.x) / (b.x - a.x) - 1.25) < 1e-6, "zoom in by 1.25");
  await page.mouse.move(600, 300);
  await page.mouse.down();
  await page.mouse.move(700, 340, { steps: 4 });
  await page.mouse.up();
  const a3 = await viewer(page, "toScreen(1, 0)");
  assert.ok(Math.abs(a3.x - a2.x - 100) < 1 && Math.abs(a3.y - a2.y - 40) < 1, "dragged by (100, 40)");
  await page.locator("#fit").click();
  const a4 = await viewer(page, "toScreen(1, 0)");
  assert.ok(Math.abs(a4.x - a.x) < 1 && Math.abs(a4.y - a.y) < 1, "fit restores the view");
  await page.close();
  assert.deepEqual(errors, []);
});

// pixel checks of a screenshot: the robot, the plume and the trajectory
async function shoot(page) {
  return decodePng(await page.screenshot());
}

test("a screenshot shows the robot, the plume and the trajectory", async () => {
  const page = await open("run.html");
  const style = await page.evaluate(() => JSON.parse(document.getElementById("plumetrace-data").textContent).style);
  const pathColors = style.states.map(hex);
  const onPath = (p) => pathColors.some((c) => near(p, c, 30));
  const arena = await page.locator("#view").boundingBox();
  const whole = { x0: arena.x, y0: arena.y, x1: arena.x + arena.width, y1: arena.y + arena.height };

  // at release: no trajectory drawn yet
  const first = await shoot(page);
  assert.ok(count(first, whole, onPath) < 20, "no trajectory at the first frame");

  await viewer(page, "setFrame(3000)");
  const img = await shoot(page);
  // the robot: its colour fills the disc around where the page says it is
  const r = await viewer(page, "robotOnScreen()");
  const robot = { x0: r.x - r.radius, y0: r.y - r.radius, x1: r.x + r.radius, y1: r.y + r.radius };
  const red = count(img, robot, (p) => near(p, hex(style.robot), 40));
  assert.ok(red > 0.3 * r.radius * r.radius, `robot pixels ${red}`);
  // the plume: bluish pixels between the source and 4 m downwind, along y = 0
  const s = await viewer(page, "toScreen(1.5, 0.5)"), e = await viewer(page, "toScreen(5, -0.5)");
  const plume = count(img, { x0: s.x, y0: s.y, x1: e.x, y1: e.y }, bluish);
  assert.ok(plume > 0.3 * (e.x - s.x) * (e.y - s.y), `plume pixels ${plume}`);
  // the plume is not everywhere: the arena's far corner has none
  const c0 = await viewer(page, "toScreen(1, 1.9)"), c1 = await viewer(page, "toScreen(4, 1.5)");
  assert.ok(count(img, { x0: c0.x, y0: c0.y, x1: c1.x, y1: c1.y }, bluish) < 10, "no plume far off the axis");
  // the trajectory: pixels in the state colours, many more than at release
  const path = count(img, whole, onPath);
  assert.ok(path > 400, `trajectory pixels ${path}`);
  await page.close();
  assert.deepEqual(errors, []);
});

test("the static SVG figure draws the same layers", async () => {
  const svg = readFileSync(join(dir, "run.svg"), "utf8");
  assert.ok(!/https?:\/\/(?!www\.w3\.org\/2000\/svg)/.test(svg), "no external resource");
  const page = await open("run.svg");
  const img = await shoot(page);
  const style = JSON.parse(readFileSync(join(dir, "run.html"), "utf8").match(/<script id="plumetrace-data" type="application\/json">(.*?)<\/script>/s)[1]).style;
  const all = { x0: 0, y0: 0, x1: img.width, y1: img.height };
  assert.ok(count(img, all, (p) => near(p, hex(style.robot), 40)) > 20, "robot");
  assert.ok(count(img, all, bluish) > 5000, "plume");
  for (const c of style.states) assert.ok(count(img, all, (p) => near(p, hex(c), 30)) > 50, `trajectory in ${c}`);
  await page.close();
  assert.deepEqual(errors, []);
});

test("names from the run are shown as text, not markup", async () => {
  // a controller of the user's may name its states anything
  const trace = JSON.parse(readFileSync(join(dir, "run.json"), "utf8"));
  trace.result.algorithm = "<b id='injected'>mine</b>";
  trace.steps.state = trace.steps.state.map((s) => (s === "upwind" ? "<!--<script><i id='state'>up</i>" : s));
  writeFileSync(join(dir, "odd.json"), JSON.stringify(trace));
  plumetrace("view", "odd.json", "-o", "odd.html");
  const page = await open("odd.html");
  assert.equal(await page.locator("#injected, #state").count(), 0);
  assert.equal(await page.locator("#p-state").textContent(), "<!--<script><i id='state'>up</i>");
  assert.match(await page.locator("#outcome").textContent(), /<b id='injected'>mine<\/b>, seed 1/);
  await page.close();
  assert.deepEqual(errors, []);
});

test("a long run is thinned to its frame budget and still plays", async () => {
  const page = await open("long.html");
  const data = await page.evaluate(() => JSON.parse(document.getElementById("plumetrace-data").textContent));
  assert.equal(data.steps, 37501);
  assert.ok(data.frames.time.length <= 12000 + 10, `frames ${data.frames.time.length}`);
  assert.ok(data.snapshots.time.length <= 600);
  assert.equal(data.frames.time.at(-1), 1200);
  await page.locator("#last").click();
  assert.match(await page.locator("#p-time").textContent(), /^1200\.00 s/);
  // drawing cost of the last frame (the longest path), reported for docs/performance.md
  const ms = await viewer(page, "drawTime(20)");
  console.log(`# long run: ${data.steps} steps, ${data.frames.time.length} frames, ${data.path.time.length} path vertices, ${data.snapshots.time.length} snapshots; one frame drawn in ${ms.toFixed(2)} ms`);
  await page.close();
  assert.deepEqual(errors, []);
});
