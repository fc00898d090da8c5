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
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
const context = await browser.newContext({ viewport: { width: 1400, height: 860 }, acceptDownloads: true });
const page = await context.newPage();
const errors = [];
page.on('pageerror', (e) => errors.push(String(e)));
page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });

const generation = async () => +(await page.evaluate(() => document.body.dataset.generation || 0));
const waitForGeneration = async (after) =>
  page.waitForFunction((g) => +(document.body.dataset.generation || 0) > g, after, { timeout: 120000 });
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

// 2. A slider: r.SSGI.Quality to 1. The image and the times change.
const quality = page.locator('.param[data-key="cvar:r.SSGI.Quality"] input[type=range]');
let g = await generation();
await quality.fill('1');
await waitForGeneration(g);
await page.waitForTimeout(200);
results.timingAfter = await page.locator('#timing').textContent();
results.imageChanged = !(await canvasBytes()).equals(before);
results.settings = await page.evaluate(() => window.workbench.params.settings);
await shot('02_quality_1.png');

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
