// The run viewer in a real browser: Debian's chromium driven by playwright-core.
// Run by ctest (test "browser_viewer") with PLUMETRACE_CLI set; PLUMETRACE_CHROMIUM overrides
// the browser (default /usr/bin/chromium). scripts/setup.sh installs both.
import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";
import { inflateSync } from "node:zlib";

const cli = process.env.PLUMETRACE_CLI;
const root = join(dirname(fileURLToPath(import.meta.url)), "..", "..");
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
// the plume's grey (filaments of any shade over the floor), and the detection region's yellow
const greyish = (p) => Math.max(...p) - Math.min(...p) < 14 && p[0] < 236 && p[0] > 90;
const yellowish = (p) => p[0] > 200 && Math.abs(p[0] - p[1]) < 32 && p[2] < 125;
const white = (p) => p[0] >= 250 && p[1] >= 250 && p[2] >= 250;

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
  // a wind at 18 degrees that carries the plume through the upper wall
  plumetrace("run", "--set", "wind.vy=0.3", "--view", "clip.html");
  plumetrace("run", "--set", "wind.vy=0.3", "--view", "clip.svg");
  // a meandering wind: the wind at the robot turns as the run goes
  plumetrace("run", join(root, "scenarios", "meander-strong.toml"), "--trace", "meander.json",
             "--snapshot-interval", "1");
  plumetrace("view", "meander.json", "-o", "meander.html");
  // a long run (37 500 steps): a tight spiral that never smells odor until the timeout
  plumetrace("run", "--algorithm", "surge-spiral", "--set", "surge_spiral.d_gap=0.02",
             "--set", "odor.threshold=1e15", "--view", "long.html");
  // a team of three robots on one plume, 2 minutes
  plumetrace("run", "--set", "team.count=3", "--set", "supervisor.timeout=120", "--trace",
             "team.json", "--snapshot-interval", "1");
  plumetrace("view", "team.json", "-o", "team.html");
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

async function open(file, viewport = { width: 1280, height: 720 }) {
  const page = await browser.newPage({ viewport });
  page.on("console", (m) => { if (m.type() === "error") errors.push(`${file}: ${m.text()}`); });
  page.on("pageerror", (e) => errors.push(`${file}: ${e.message}`));
  // the page must not reach the network: anything but file: is recorded and refused
  await page.route("**/*", (route) => {
    const url = route.request().url();
    if (url.startsWith("file:")) return route.continue();
    offline.push(url);
    return route.abort();
  });
  const [name, hash] = file.split("#");
  await page.goto(pathToFileURL(join(dir, name)).href + (hash === undefined ? "" : `#${hash}`));
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
  // the true wind field's light grey arrows off, so that grey is the plume's
  await page.locator("#layer-wind_field").click();
  const img = await shoot(page);
  // the robot: its colour fills the disc around where the page says it is
  const r = await viewer(page, "robotOnScreen()");
  const robot = { x0: r.x - r.radius, y0: r.y - r.radius, x1: r.x + r.radius, y1: r.y + r.radius };
  const red = count(img, robot, (p) => near(p, hex(style.robot), 40));
  assert.ok(red > 0.3 * r.radius * r.radius, `robot pixels ${red}`);
  // the plume: grey pixels between the source and 4 m downwind, along y = 0
  const s = await viewer(page, "toScreen(1.5, 0.2)"), e = await viewer(page, "toScreen(5, -0.2)");
  const plume = count(img, { x0: s.x, y0: s.y, x1: e.x, y1: e.y }, greyish);
  assert.ok(plume > 0.3 * (e.x - s.x) * (e.y - s.y), `plume pixels ${plume}`);
  // the plume is not everywhere: the arena's far corner has none
  const c0 = await viewer(page, "toScreen(1, 1.9)"), c1 = await viewer(page, "toScreen(4, 1.5)");
  assert.ok(count(img, { x0: c0.x, y0: c0.y, x1: c1.x, y1: c1.y }, greyish) < 10, "no plume far off the axis");
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
  assert.ok(count(img, all, greyish) > 5000, "plume");
  assert.ok(count(img, all, yellowish) > 50, "detection region");
  for (const c of style.states) assert.ok(count(img, all, (p) => near(p, hex(c), 30)) > 50, `trajectory in ${c}`);
  await page.close();
  assert.deepEqual(errors, []);
});

test("names from the run are shown as text, not markup", async () => {
  // a controller of the user's may name its states anything
  const trace = JSON.parse(readFileSync(join(dir, "run.json"), "utf8"));
  trace.result.algorithm = "<b id='injected'>mine</b>";
  trace.steps.state_names = trace.steps.state_names.map((s) => (s === "upwind" ? "<!--<script><i id='state'>up</i>" : s));
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
  const robot = data.robots[0];
  assert.ok(robot.frames.time.length <= 12000 + 10, `frames ${robot.frames.time.length}`);
  assert.ok(data.snapshots.time.length <= 600);
  assert.equal(robot.frames.time.at(-1), 1200);
  await page.locator("#last").click();
  assert.match(await page.locator("#p-time").textContent(), /^1200\.00 s/);
  // drawing cost of the last frame (the longest path), reported for docs/performance.md
  const ms = await viewer(page, "drawTime(20)");
  console.log(`# long run: ${data.steps} steps, ${robot.frames.time.length} frames, ${robot.path.time.length} path vertices, ${data.snapshots.time.length} snapshots; one frame drawn in ${ms.toFixed(2)} ms`);
  await page.close();
  assert.deepEqual(errors, []);
});

test("#t= in the address opens the page at that time, and a link keeps it", async () => {
  const page = await open("run.html#t=96");
  assert.equal(await viewer(page, "time()"), 96);
  assert.match(await page.locator("#p-time").textContent(), /^96\.00 s of/);
  assert.equal(await page.locator("#here").getAttribute("href"), "#t=96.00");
  // a new time in the address moves there: the last frame at or before it
  await page.evaluate(() => { location.hash = "#t=50.5"; });
  await page.waitForFunction(() => window.plumetraceViewer.time() <= 50.5 && window.plumetraceViewer.time() > 50.4);
  // beyond the end: the last frame
  await page.evaluate(() => { location.hash = "#t=1e9"; });
  await page.waitForFunction(() => window.plumetraceViewer.frame() === window.plumetraceViewer.frames - 1);
  await page.close();
  assert.deepEqual(errors, []);
});

test("the detection region is drawn where odor is perceivable, and its switch hides it", async () => {
  const page = await open("run.html#t=96");
  assert.ok((await viewer(page, "regionCells()")) > 50, "cells in odor at 96 s");
  const grid = await viewer(page, "regionGrid()");
  assert.equal(grid.nx, 320);
  assert.equal(grid.ny, 80);
  const arena = await page.locator("#view").boundingBox();
  const whole = { x0: arena.x, y0: arena.y, x1: arena.x + arena.width, y1: arena.y + arena.height };
  const shown = count(await shoot(page), whole, yellowish);
  assert.ok(shown > 100, `region pixels ${shown}`);
  await page.locator("#layer-region").click();
  assert.equal((await viewer(page, "layers()")).region, false);
  assert.equal(count(await shoot(page), whole, yellowish), 0, "no region pixels once hidden");
  await page.locator("#layer-region").click();
  assert.ok(count(await shoot(page), whole, yellowish) > 100, "shown again");
  await page.close();
  assert.deepEqual(errors, []);
});

// the pixels just above the arena's upper wall, over its whole length, and just below it
async function aboveAndBelowTheUpperWall(page, toScreen, band) {
  const a = await toScreen(0, 2), b = await toScreen(16, 2);
  const img = await shoot(page);
  const above = count(img, { x0: a.x, y0: a.y - band, x1: b.x, y1: a.y - 4 }, (p) => !white(p));
  const below = count(img, { x0: a.x, y0: a.y + 4, x1: b.x, y1: a.y + 40 }, greyish);
  return { above, below };
}

test("filaments are clipped to the arena, in the page and in the figure", async () => {
  const page = await open("clip.html");
  await page.locator("#last").click();
  for (const layer of ["path", "wind", "detections"]) await page.locator(`#layer-${layer}`).click();
  const { above, below } = await aboveAndBelowTheUpperWall(page, (x, y) => viewer(page, `toScreen(${x}, ${y})`), 40);
  assert.ok(below > 500, `the plume reaches the upper wall (${below} grey pixels under it)`);
  assert.equal(above, 0, "nothing is drawn above the upper wall");
  await page.close();

  // the figure: the arena's rectangle gives the mapping
  const svg = await open("clip.svg");
  const r = await svg.evaluate(() => {
    const a = document.getElementById("arena");
    return { x: +a.getAttribute("x"), y: +a.getAttribute("y"), w: +a.getAttribute("width"), h: +a.getAttribute("height") };
  });
  // why: 12 px, the room between the wall and the caption above it
  const fig = await aboveAndBelowTheUpperWall(svg, (x, y) => ({ x: r.x + (x / 16) * r.w, y: r.y + ((2 - y) / 4) * r.h }), 12);
  assert.ok(fig.below > 500, `the figure's plume reaches the upper wall (${fig.below})`);
  assert.equal(fig.above, 0, "the figure draws nothing above the upper wall");
  await svg.close();
  assert.deepEqual(errors, []);
});

test("the page has a scale bar and the figure axes in metres", async () => {
  const page = await open("run.html");
  const bar = await viewer(page, "scaleBar()");
  const a = await viewer(page, "toScreen(0, 0)"), b = await viewer(page, "toScreen(1, 0)");
  assert.ok(Math.abs(bar.px - bar.metres * (b.x - a.x)) < 1e-6, "the bar's length is its metres on screen");
  assert.ok(bar.px >= 80 && bar.px < 400, `bar ${bar.px} px`);
  const img = await shoot(page);
  const dark = count(img, { x0: bar.x, y0: bar.y - 1, x1: bar.x + bar.px, y1: bar.y + 2 }, (p) => p[0] < 80);
  assert.ok(dark > 0.8 * bar.px, `the bar is drawn (${dark} px)`);
  await page.locator("#zoom-in").click();
  const zoomed = await viewer(page, "scaleBar()");
  assert.ok(zoomed.px / zoomed.metres > 1.2 * (bar.px / bar.metres), "the bar follows the zoom");
  await page.close();

  const svg = await open("run.svg");
  const ticks = await svg.evaluate(() => [...document.querySelectorAll("#axes text")].map((t) => t.textContent));
  for (const label of ["0", "8", "16", "-2", "2", "x (m), wind along +x", "y (m)"]) assert.ok(ticks.includes(label), label);
  assert.match(await svg.locator("#scale-bar text").textContent(), /^[125]0* m$/);
  await svg.close();
  assert.deepEqual(errors, []);
});

test("the legend fits a 900 px window, in the page and in the figure", async () => {
  const page = await open("run.html", { width: 900, height: 720 });
  const boxes = await page.evaluate(() => [...document.querySelectorAll("#legend > *")].map((e) => {
    const r = e.getBoundingClientRect();
    return { text: e.textContent, right: r.right, bottom: r.bottom };
  }));
  assert.ok(boxes.length >= 12, `${boxes.length} legend entries`);
  for (const b of boxes) {
    assert.ok(b.right <= 900 && b.bottom <= 720, `legend entry "${b.text}" at ${b.right}, ${b.bottom}`);
  }
  // the canvas keeps most of the window
  const stage = await page.locator("#view").boundingBox();
  assert.ok(stage.width > 550 && stage.height > 400, `canvas ${stage.width} x ${stage.height}`);
  await page.close();

  const svg = await open("run.svg", { width: 900, height: 720 });
  const fig = await svg.evaluate(() => {
    const root = document.documentElement.getBoundingClientRect();
    const legend = [...document.querySelectorAll("#legend text")].map((t) => t.getBoundingClientRect().right);
    return { width: root.width, right: Math.max(...legend) };
  });
  assert.ok(fig.width <= 900 && fig.right <= 900, `figure ${fig.width} px, legend to ${fig.right} px`);
  await svg.close();
  assert.deepEqual(errors, []);
});

test("in a meandering wind the compass shows the true wind the trace recorded at the robot", async () => {
  const trace = JSON.parse(readFileSync(join(dir, "meander.json"), "utf8"));
  const readings = [];
  for (const t of [5, 15]) {
    const page = await open(`meander.html#t=${t}`);
    const compass = await viewer(page, "compass()");
    const u = trace.steps.true_wind_x[compass.step], v = trace.steps.true_wind_y[compass.step];
    assert.equal(trace.steps.time[compass.step], await viewer(page, "time()"));
    assert.ok(Math.abs(compass.truth.u - u) <= 1e-5 && Math.abs(compass.truth.v - v) <= 1e-5,
              `compass (${compass.truth.u}, ${compass.truth.v}), trace (${u}, ${v}) at step ${compass.step}`);
    // the panel reads the same wind
    const deg = (Math.atan2(v, u) * 180) / Math.PI;
    assert.equal(await page.locator("#p-true-wind").textContent(),
                 `${Math.hypot(u, v).toFixed(2)} m/s at ${deg.toFixed(0)}\u00b0, at the robot`);
    readings.push(compass.truth);
    await page.close();
  }
  // the wind at the robot is not the mean wind, and it turned between the two times
  assert.ok(readings.some((w) => Math.abs(w.u - 0.9) > 1e-3 || Math.abs(w.v) > 1e-3), "a meander, not the mean");
  const turn = Math.abs(Math.atan2(readings[0].v, readings[0].u) - Math.atan2(readings[1].v, readings[1].u));
  assert.ok(turn > 0.01, `the wind turned by ${turn} rad`);
  assert.deepEqual(errors, []);
});

test("a team's robots are drawn each in its colour, with a row each the panel can follow", async () => {
  const trace = JSON.parse(readFileSync(join(dir, "team.json"), "utf8"));
  const page = await open("team.html#t=60");
  assert.equal(await viewer(page, "robots"), 3);
  const rows = page.locator("#robots tr");
  assert.equal(await rows.count(), 3);
  // each row says its robot's outcome, as the trace has it
  const outcomes = [trace.result, ...trace.teammates.map((m) => m.result)].map((r) => r.outcome);
  for (let k = 0; k < 3; ++k) assert.match(await rows.nth(k).textContent(), new RegExp(`robot ${k}.*${outcomes[k]}`));
  // each robot's disc in its own colour, robot 0 in a robot alone's
  await page.locator("#layer-wind_field").click();
  const style = await page.evaluate(() => JSON.parse(document.getElementById("plumetrace-data").textContent).style);
  assert.equal(style.robots[0], style.robot);
  assert.equal(new Set(style.robots).size, style.robots.length);
  const img = await shoot(page);
  for (let k = 0; k < 3; ++k) {
    const r = await viewer(page, `robotOnScreen(${k})`);
    const box = { x0: r.x - r.radius, y0: r.y - r.radius, x1: r.x + r.radius, y1: r.y + r.radius };
    const pixels = count(img, box, (p) => near(p, hex(r.color), 40));
    assert.ok(pixels > 0.3 * r.radius * r.radius, `robot ${k} pixels ${pixels} in ${r.color}`);
  }
  // a click on a row makes the panel follow that robot
  await rows.nth(2).click();
  assert.equal(await viewer(page, "selected()"), 2);
  assert.equal(await page.locator("#now-title").textContent(), "Now: robot 2");
  assert.match(await page.locator("#outcome").textContent(), /robot 2/);
  // the paths in their robots' colours, or in their states'
  assert.equal(await page.locator("#path-colour").inputValue(), "robot");
  await page.locator("#path-colour").selectOption("state");
  await page.close();
  assert.deepEqual(errors, []);
});
