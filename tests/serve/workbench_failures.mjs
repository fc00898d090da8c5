// The workbench page when things go wrong (headless Chromium, Playwright): a first frame that
// fails, the server lost and back, and a cvar the config's params shadow. Starts its own
// `framepass serve` processes; what the page showed goes to OUT/results.json for
// tests/serve/test_browser.py, with a screenshot of each state.
//
//   node workbench_failures.mjs OUT CONFIG MISSING_CAPTURE_CONFIG PINNED_QUALITY_CONFIG
//
// FRAMEPASS: the executable; FP_NODE_PREFIX and CHROMIUM as for workbench.mjs.
import { createRequire } from 'module';
import { spawn } from 'child_process';
import fs from 'fs';
import path from 'path';

const require = createRequire(path.join(process.env.FP_NODE_PREFIX, 'package.json'));
const { chromium } = require('playwright-core');

const [out, config, missingConfig, pinnedConfig] = process.argv.slice(2);
fs.mkdirSync(out, { recursive: true });
const results = {};

// `framepass serve CONFIG --port PORT`, resolved once it prints its URL.
function serve(cfg, port = 0) {
  const child = spawn(process.env.FRAMEPASS, ['serve', cfg, '--port', String(port)], { stdio: ['ignore', 'pipe', 'pipe'] });
  return new Promise((resolve, reject) => {
    let text = '';
    child.stdout.on('data', (d) => {
      text += d;
      const m = text.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) resolve({ child, url: m[0], port: +m[1] });
    });
    child.on('exit', (code) => reject(new Error(`serve exited ${code}: ${text}`)));
  });
}
const stop = (server) => new Promise((resolve) => { server.child.once('exit', resolve); server.child.kill('SIGINT'); });

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  // WebGL2 on SwiftShader, the page composited in software: what Chromium does where no GPU
  // is (compositing through SwiftShader costs about 30 ms of CPU a frame, drawn or not).
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist',
         '--disable-gpu-compositing', ...(process.env.FP_CHROMIUM_FLAGS || '').split(' ').filter(Boolean)],
});
const page = await (await browser.newContext({ viewport: { width: 1400, height: 860 } })).newPage();
const status = () => page.locator('#status').textContent();
const waitForText = (id, pattern) => page.waitForFunction(([i, p]) => new RegExp(p).test(document.getElementById(i).textContent), [id, pattern], { timeout: 120000 });
const waitForStatus = (pattern) => waitForText('status', pattern);
const connection = () => page.locator('#connection').textContent();

// 1. The first frame fails: the page says why instead of waiting forever.
let server = await serve(missingConfig);
await page.goto(server.url);
await waitForStatus('first frame failed');
results.firstFrame = { status: await status(), error: await page.locator('#status').getAttribute('class') };
await page.screenshot({ path: path.join(out, 'f1_first_frame_failed.png') });
await stop(server);

// 2. The server lost and back on the same port: said, and the controls follow the new server.
server = await serve(config);
await page.goto(server.url);
await page.waitForFunction(() => +(document.body.dataset.generation || 0) >= 1, null, { timeout: 120000 });
const slider = page.locator('.param[data-key="cvar:r.SSGI.Quality"] input[type=number]');
const loaded = await slider.inputValue();
await slider.fill('1');
await slider.press('Enter');
await page.waitForFunction(() => +(document.body.dataset.generation || 0) >= 2, null, { timeout: 120000 });
const port = server.port;
await stop(server);
await waitForText('connection', 'lost the server');
results.lost = { status: await connection(), connection: await page.evaluate(() => document.body.dataset.connection), slider: await slider.inputValue() };
await page.screenshot({ path: path.join(out, 'f2_server_lost.png') });
server = await serve(config, port);
await waitForText('connection', 'reconnected');
await page.waitForTimeout(300);
results.back = {
  status: await connection(), connection: await page.evaluate(() => document.body.dataset.connection),
  slider: await slider.inputValue(), loaded,
  server: (await (await fetch(server.url + 'api/params')).json()).cvars.find((c) => c.name === 'r.SSGI.Quality').value,
};
await page.screenshot({ path: path.join(out, 'f3_reconnected.png') });
await stop(server);

// 3. A cvar the config's params shadow says so beside its slider.
server = await serve(pinnedConfig);
await page.goto(server.url);
await page.waitForFunction(() => +(document.body.dataset.generation || 0) >= 1, null, { timeout: 120000 });
const note = page.locator('.param[data-key="cvar:r.SSGI.Quality"] .shadow-note');
results.shadowed = { note: await note.textContent(), marked: await page.locator('.param[data-key="cvar:r.SSGI.Quality"]').getAttribute('class') };
await note.scrollIntoViewIfNeeded();
await page.screenshot({ path: path.join(out, 'f4_shadowed_cvar.png') });
await stop(server);

fs.writeFileSync(path.join(out, 'results.json'), JSON.stringify(results, null, 2));
await browser.close();
