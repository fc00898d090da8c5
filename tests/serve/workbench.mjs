// Drives the workbench page in headless Chromium (Playwright): the steps a look-dev artist takes,
// a screenshot after each, and what the page showed written to OUT/results.json for
// tests/serve/test_browser.py to check against the command line.
//
//   node workbench.mjs URL OUT [--latency N]
//
// FP_NODE_PREFIX: the folder whose node_modules holds playwright-core; CHROMIUM: the browser.
// With --latency N it also moves the SSGI quality slider N more times and records, per move,
// when the change was sent, run, fetched and drawn (examples/bench/workbench_latency.py).
import { createRequire } from 'module';
import fs from 'fs';
import path from 'path';

const require = createRequire(path.join(process.env.FP_NODE_PREFIX, 'package.json'));
const { chromium } = require('playwright-core');

const [url, out] = process.argv.slice(2);
const latencyRuns = process.argv.includes('--latency') ? +process.argv[process.argv.indexOf('--latency') + 1] : 0;
fs.mkdirSync(out, { recursive: true });
const results = { steps: [] };

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  // WebGL2 on SwiftShader, the page composited in software: what Chromium does where no GPU
  // is (compositing through SwiftShader costs about 30 ms of CPU a frame, drawn or not).
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
         '--disable-gpu-compositing', ...(process.env.FP_CHROMIUM_FLAGS || '').split(' ').filter(Boolean)],
});
const context = await browser.newContext({ viewport: { width: 1400, height: 860 }, acceptDownloads: true });
const page = await context.newPage();
const errors = [];
page.on('pageerror', (e) => errors.push(String(e)));
page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });

const generation = async () => +(await page.evaluate(() => document.body.dataset.generation || 0));
// Polled on a timer, not every animation frame: a frame each 16 ms is the whole page drawn again,
// which with software rendering takes a core from the server the latency figures measure.
const waitForGeneration = async (after) =>
  page.waitForFunction((g) => +(document.body.dataset.generation || 0) > g, after, { timeout: 120000, polling: 20 });
const shot = async (name) => {
  const file = path.join(out, name);
  await page.screenshot({ path: file });
  results.steps.push(file);
};
// The colour of the canvas at a fraction of the image's width, on its middle row.
const canvasColor = (fx) => page.evaluate((fx) => {
  const v = window.workbench.viewer;
  const c = document.createElement('canvas');
  c.width = v.canvas.width; c.height = v.canvas.height;
  const g = c.getContext('2d');
  g.drawImage(v.canvas, 0, 0);
  const x = Math.floor(v.state.pan[0] + v.a.width * fx * v.state.zoom);
  const y = Math.floor(v.state.pan[1] + v.a.height * 0.5 * v.state.zoom);
  return Array.from(g.getImageData(x, y, 1, 1).data);
}, fx);
const canvasBytes = async () => page.locator('#canvas').screenshot();

// 1. The page: the chain as a graph, the image, the report.
await page.goto(url);
await page.waitForFunction(() => +(document.body.dataset.generation || 0) >= 1 && window.workbench.viewer.a, null, { timeout: 120000 });
await page.waitForTimeout(200);
results.graphNodes = await page.locator('#graph .node').count();
results.graphPorts = await page.locator('#graph .port').count();
results.reportRows = await page.locator('#report tbody tr').count();
results.errorRows = await page.locator('#errors tbody tr').count();
results.shown = await page.evaluate(() => ({ ...window.workbench.shown }));
results.timingBefore = await page.locator('#timing').textContent();
await shot('01_loaded.png');
const before = await canvasBytes();

// 1b. Colour: display.image (display-referred) and the display's input (colour, through the
// view) drawn on the canvas; the PNG `framepass run` wrote for the same settings read in this
// browser with no colour conversion. test_browser.py compares them (±1).
const imagePixels = [[10, 10], [48, 32], [70, 50], [90, 5]];
const canvasAt = (pixels) => page.evaluate((pixels) => {
  const v = window.workbench.viewer;
  const c = document.createElement('canvas');
  c.width = v.canvas.width; c.height = v.canvas.height;
  const g = c.getContext('2d');
  g.drawImage(v.canvas, 0, 0);
  return pixels.map(([x, y]) => Array.from(g.getImageData(Math.floor(v.state.pan[0] + (x + 0.5) * v.state.zoom),
    Math.floor(v.state.pan[1] + (y + 0.5) * v.state.zoom), 1, 1).data));
}, pixels);
const showA = async (name) => {
  await page.selectOption('#buffer-a', name);
  await page.waitForFunction((n) => window.workbench.viewer.a?.name === n, name, { timeout: 60000 });
  await page.waitForTimeout(100);
};
const shownBefore = await page.evaluate(() => ({ ...window.workbench.shown }));
const readPng = (file) => page.evaluate(async ([b64, pixels]) => {
    const blob = await (await fetch(`data:image/png;base64,${b64}`)).blob();
    const bitmap = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
    const c = document.createElement('canvas');
    c.width = bitmap.width; c.height = bitmap.height;
    const g = c.getContext('2d');
    g.drawImage(bitmap, 0, 0);
    return pixels.map(([x, y]) => Array.from(g.getImageData(x, y, 1, 1).data));
  }, [fs.readFileSync(file).toString('base64'), imagePixels]);
if (process.env.FP_RUN_PNG) {
  results.colour = { pixels: imagePixels, png: await readPng(process.env.FP_RUN_PNG) };
  await showA('display.image');
  results.colour.display = await canvasAt(imagePixels);
  results.colour.displayLabel = await page.locator('#label-a').textContent();
  await shot('01b_display_image.png');
  await showA('diffuse_indirect_composite.color');
  results.colour.composite = await canvasAt(imagePixels);
  results.colour.compositeLabel = await page.locator('#label-a').textContent();
  // Unreal's film view against `run` with the display's tonemapper set to ue4.27-film.
  await page.selectOption('#view', 'ue4.27-film');
  await page.waitForFunction(() => window.workbench.viewer.state.film === 1, null, { timeout: 60000 });
  await page.waitForTimeout(100);
  results.colour.film = await canvasAt(imagePixels);
  results.colour.filmPng = await readPng(process.env.FP_RUN_FILM_PNG);
  results.colour.filmLabel = await page.locator('#label-a').textContent();
  await shot('01c_film_view.png');
  await page.selectOption('#view', 'Standard');
  await page.waitForFunction(() => window.workbench.viewer.state.film === 0, null, { timeout: 60000 });
  await showA(shownBefore.a);
}
results.labels = { a: await page.locator('#label-a').textContent(), b: await page.locator('#label-b').textContent() };

// 1c. The graph fits its panel, and every name fits its box.
results.graph = await page.evaluate(() => {
  const panel = document.getElementById('graph');
  const svg = panel.querySelector('svg');
  const overflowing = [];
  for (const node of panel.querySelectorAll('.node')) {
    const box = node.querySelector('rect').getBBox();
    for (const t of node.querySelectorAll('text'))
      if (t.getBBox().x + t.getBBox().width > box.x + box.width + 0.5) overflowing.push(t.textContent);
  }
  return { panelWidth: panel.clientWidth, svgWidth: svg.getBoundingClientRect().width, overflowing };
});

// 1d. Pin what A shows at the settings as loaded (key P), to compare against after the change.
await page.evaluate(() => document.activeElement.blur());
await page.keyboard.press('p');
results.snapshotLabel = await page.locator('#snapshots li').first().textContent();

// 1e. FLIP beside the error figures: ssgi_vs_full's flip parameter set to hdr on the page, the
// errors table then has a FLIP column with what /api/report says; set back to off after.
{
  const flipKey = '.param[data-key="set:ssgi_vs_full.flip"]';
  await page.evaluate((k) => { document.querySelector(k).closest('details').open = true; }, flipKey);
  const setFlip = async (mode) => {
    const g = await generation();
    await page.selectOption(`${flipKey} select`, mode);
    await waitForGeneration(g);
    await page.waitForTimeout(200);
  };
  await setFlip('hdr');
  results.flip = await page.evaluate(async () => {
    const t = document.getElementById('errors');
    const heads = [...t.tHead.rows[0].cells].map((c) => c.textContent);
    const rows = {};
    for (const r of t.tBodies[0].rows) rows[r.cells[0].textContent] = r.cells[heads.indexOf('flip')]?.textContent;
    const report = await (await fetch('/api/report')).json();
    return { heads, rows, api: report.errors.ssgi_vs_full.flip };
  });
  await shot('01e_flip_column.png');
  await setFlip('off');
  results.flipAfter = await page.evaluate(() => [...document.getElementById('errors').tHead.rows[0].cells].map((c) => c.textContent));
}

// 2. A slider: r.SSGI.Quality to 1. The image and the times change.
const quality = page.locator('.param[data-key="cvar:r.SSGI.Quality"] input[type=range]');
let g = await generation();
await quality.fill('1');
await waitForGeneration(g);
await page.waitForTimeout(200);
results.timingAfter = await page.locator('#timing').textContent();
results.methods = await page.evaluate(() => ({
  now: Array.from(document.querySelectorAll('#methods .now circle'), (c) => c.dataset.measure),
  earlier: document.querySelectorAll('#methods .earlier circle').length,
}));
results.imageChanged = !(await canvasBytes()).equals(before);
results.settings = await page.evaluate(() => window.workbench.params.settings);
await shot('02_quality_1.png');

// 2b. The snapshot as B, and statistics over a shift-dragged rectangle: A's mean and the RMSE of
// A (quality 1) against the snapshot (quality 4, as loaded).
await page.locator('#snapshots li button', { hasText: 'as B' }).first().click();
results.snapshotB = await page.locator('#label-b').textContent();
const rect = [20, 10, 44, 30];  // [x0, y0, x1, y1): pixels x0..x1-1, y0..y1-1
const at = (x, y) => page.evaluate(([x, y]) => {
  const v = window.workbench.viewer, r = v.canvas.getBoundingClientRect();
  return [r.left + v.state.pan[0] + (x + 0.5) * v.state.zoom, r.top + v.state.pan[1] + (y + 0.5) * v.state.zoom];
}, [x, y]);
const [sx, sy] = await at(rect[0], rect[1]);
const [ex, ey] = await at(rect[2] - 1, rect[3] - 1);
await page.keyboard.down('Shift');
await page.mouse.move(sx, sy);
await page.mouse.down();
await page.mouse.move(ex, ey, { steps: 4 });
await page.mouse.up();
await page.keyboard.up('Shift');
results.rect = { asked: rect, stats: await page.evaluate(() => window.workbench.rectStats),
                 text: await page.locator('#rect-stats').textContent() };
await shot('02b_snapshot_rectangle.png');
await page.selectOption('#buffer-b', 'Truth.DiffuseIndirectOneBounce');
await page.waitForFunction(() => window.workbench.viewer.b?.name === 'Truth.DiffuseIndirectOneBounce', null, { timeout: 60000 });

// 3. Wipe between A (the pass output) and B (its truth); then the difference.
await page.selectOption('#mode', 'b');
const bRight = await canvasColor(0.75);
await page.selectOption('#mode', 'a');
const aLeft = await canvasColor(0.25), aRight = await canvasColor(0.75);
await page.selectOption('#mode', 'wipe');
await page.locator('#wipe').fill('0.5');
results.wipe = { aLeft, aRight, bRight, wipeLeft: await canvasColor(0.25), wipeRight: await canvasColor(0.75) };
await shot('03_wipe.png');
await page.selectOption('#mode', 'diff');
await shot('04_difference.png');
await page.selectOption('#mode', 'a');
await page.locator('#false-color').check();
await shot('05_false_colour.png');
await page.locator('#false-color').uncheck();
// 3a. The two ways the viewer draws (once an image pixel then placed, or once a canvas pixel)
// give the same canvas in every mode.
const drawnBothWays = async () => {
  const colours = async () => Promise.all([0.1, 0.3, 0.5, 0.7, 0.9].map(canvasColor));
  const perImagePixel = await colours();
  await page.evaluate(() => { window.workbench.viewer.perImagePixel = false; window.workbench.viewer.draw(); });
  const perCanvasPixel = await colours();
  await page.evaluate(() => { window.workbench.viewer.perImagePixel = true; window.workbench.viewer.draw(); });
  return { perImagePixel, perCanvasPixel };
};
results.drawPaths = {};
for (const mode of ['a', 'b', 'wipe', 'diff']) {
  await page.selectOption('#mode', mode);
  results.drawPaths[mode] = await drawnBothWays();
}
await page.selectOption('#mode', 'a');
await page.locator('#false-color').check();
results.drawPaths.falseColour = await drawnBothWays();
await page.locator('#false-color').uncheck();

// 3b. tev's keys with the focus on a slider (they work) and in a number field (they type).
await page.selectOption('#mode', 'a');
const viewState = () => page.evaluate(() => ({
  ...window.workbench.viewer.state, fitted: window.workbench.viewer.fitted,
  exposure: document.getElementById('exposure').value, channel: document.getElementById('channel').value,
  mode: document.getElementById('mode').value,
  canvas: [window.workbench.viewer.canvas.clientWidth, window.workbench.viewer.canvas.clientHeight],
  image: [window.workbench.viewer.a.width, window.workbench.viewer.a.height],
}));
const keys = {};
await quality.focus();
const sliderBefore = await quality.inputValue();
const press = async (key, name) => { await page.keyboard.press(key); keys[name || key] = await viewState(); };
await press('e');
await press('Shift+E', 'E');
await press('r');
await press('r', 'r again');
await press('l');
await press('l', 'l again');
await press('2');
await press('d');
await press('1');
await press('=', '+');
await press('0');
await press('-');
keys.sliderUnchanged = (await quality.inputValue()) === sliderBefore;
keys.focusStayed = await page.evaluate(() => document.activeElement.getAttribute('aria-label'));
await page.locator('#breakdown-rays').focus();
await press('e', 'e in a number field');
keys.typed = await page.locator('#breakdown-rays').inputValue();
await page.locator('#breakdown-rays').fill('32');
await page.evaluate(() => document.activeElement.blur());
await press('f');
results.keys = keys;

// 3c. Resizing: a zoomed image keeps its centre; a fitted one is fitted again.
await page.keyboard.press('=');
const centre = async () => page.evaluate(() => {
  const v = window.workbench.viewer, s = v.state;
  return [(v.canvas.clientWidth / 2 - s.pan[0]) / s.zoom, (v.canvas.clientHeight / 2 - s.pan[1]) / s.zoom];
});
const zoomedCentre = await centre();
// A resize reaches the page with the next rendered frame (headless renders on demand).
const frames = () => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
await page.setViewportSize({ width: 1000, height: 700 });
await frames();
results.resize = { zoomedCentreBefore: zoomedCentre, zoomedCentreAfter: await centre() };
await shot('05b_resized_zoomed.png');
await page.keyboard.press('f');
await page.setViewportSize({ width: 1400, height: 860 });
await frames();
results.resize.fitted = await viewState();
await shot('05c_resized_fitted.png');

// 4. The pixel probe at a chosen pixel.
const probeAt = [Math.floor(0.6 * 96), Math.floor(0.55 * 64)];
const point = await page.evaluate(([x, y]) => {
  const v = window.workbench.viewer;
  const r = v.canvas.getBoundingClientRect();
  return [r.left + v.state.pan[0] + (x + 0.5) * v.state.zoom, r.top + v.state.pan[1] + (y + 0.5) * v.state.zoom];
}, probeAt);
await page.mouse.move(point[0], point[1]);
await page.waitForTimeout(100);
results.probe = { pixel: probeAt, text: await page.locator('#probe').textContent() };
await shot('06_probe.png');

// 5. Why: the error taken apart (few rays: this is about the page, not the figures).
await page.locator('#breakdown-rays').fill('4');
await page.click('#breakdown');
await page.waitForFunction(() => /rays, .* s\)/.test(document.getElementById('breakdown-text').textContent), null, { timeout: 120000 });
results.breakdown = await page.locator('#breakdown-text').textContent();
results.breakdownBars = await page.evaluate(() => Array.from(document.querySelectorAll('#breakdown-text .share'),
  (row) => ({ name: row.children[0].textContent, width: parseFloat(row.querySelector('.bar').style.width), value: row.children[2].textContent })));
await page.locator('#breakdown-text').scrollIntoViewIfNeeded();
await shot('07_breakdown.png');

// 6. Export the settings as a run config (the download a user gets).
const [download] = await Promise.all([page.waitForEvent('download'), page.click('#export-config')]);
results.exported = path.join(out, 'exported_config.json');
await download.saveAs(results.exported);
// What the page shows as A, as the server sent it, for the bit comparison.
results.shownA = path.join(out, 'shown_a.f32');
const bytes = await page.evaluate(() => Array.from(new Uint8Array(window.workbench.viewer.a.data.buffer)));
fs.writeFileSync(results.shownA, Buffer.from(bytes));
results.shownAShape = await page.evaluate(() => { const a = window.workbench.viewer.a; return [a.height, a.width, a.channels.length]; });

// 7. Latency: the quality slider moved back and forth.
if (latencyRuns > 0) {
  for (let i = 0; i < latencyRuns; ++i) {
    g = await generation();
    await quality.fill(String(i % 2 ? 1 : 2));
    await waitForGeneration(g);
    await page.waitForTimeout(50);
  }
  results.timings = await page.evaluate(() => window.workbench.timings);
}

results.errors = errors;
fs.writeFileSync(path.join(out, 'results.json'), JSON.stringify(results, null, 2));
await browser.close();
