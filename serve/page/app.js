// The framepass workbench page (docs/serve.md): the chain, any buffer drawn with WebGL2 (exposure,
// the OCIO view baked as a table over every half value, channel isolation, false colour, zoom and
// pan, A/B wipe, flip and difference without a request), controls made from the pass specs, and
// live re-runs through the JSON API. Plain ES module, no framework.

const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------------------------------------
// The API

async function api(path, options = {}) {
  const res = await fetch(path, options);
  if (!res.ok) {
    let message = `HTTP ${res.status}`;
    try { message = (await res.json()).error || message; } catch (e) { /* not JSON */ }
    throw new Error(message);
  }
  return res;
}
const getJSON = async (path) => (await api(path)).json();

async function fetchBuffer(name) {
  const res = await api(`/api/buffer/${encodeURIComponent(name)}?format=raw`);
  const h = (k) => res.headers.get(k);
  return {
    name,
    width: +h('X-Width'), height: +h('X-Height'),
    channels: h('X-Channels').split(','),
    frame: +h('X-Frame'), generation: +h('X-Generation'), color: h('X-Color') === '1',
    data: new Float32Array(await res.arrayBuffer()),
  };
}

// ---------------------------------------------------------------------------------------------
// The viewer: WebGL2, one draw per change of anything, no request for exposure, view, channel,
// false colour, wipe, flip, zoom or pan.

const VERTEX = `#version 300 es
in vec2 corner; out vec2 screen;
void main() { screen = corner; gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0); }`;

// The display maths of the library's display pass (passes/display/DisplayKernel.h): exposure,
// the channel mapping of a preview, the baked view looked up between neighbouring halves, clamp.
const FRAGMENT = `#version 300 es
precision highp float; precision highp int; precision highp usampler2D;
in vec2 screen; out vec4 color;
uniform sampler2D imgA, imgB, lut;
uniform int channelsA, channelsB, mode, isolate, falseColor, colorA, colorB, haveB;
uniform float gain, falseMax, wipe;
uniform vec2 canvasSize, sizeA, pan; uniform float zoom;

uint halfBitsBelow(float a) {
  if (a >= 65504.0) return 0x7BFFu;
  if (a < 6.103515625e-05) return uint(a * 16777216.0);
  uint bits = floatBitsToUint(a);
  uint e = (bits >> 23) - 127u + 15u;
  return (e << 10) | ((bits >> 13) & 0x3FFu);
}
float halfValue(uint h) {
  uint e = h >> 10, m = h & 0x3FFu;
  if (e == 0u) return float(m) * 5.9604644775390625e-08;
  return uintBitsToFloat(((e - 15u + 127u) << 23) | (m << 13));
}
float lutAt(int i, int c) { return texelFetch(lut, ivec2(i % 256, i / 256), 0)[c]; }
float lookup(float v, int c) {
  float a = abs(v);
  uint h = halfBitsBelow(a);
  int index = int(((floatBitsToUint(v) >> 31) != 0u ? 0x8000u : 0u) | h);
  float lo = lutAt(index, c);
  if (h >= 0x7BFFu) return lo;
  float x0 = halfValue(h), x1 = halfValue(h + 1u);
  return lo + (a - x0) / (x1 - x0) * (lutAt(index + 1, c) - lo);
}
float finite(float v) { return (isnan(v) || isinf(v)) ? 0.0 : v; }
vec3 viridis(float t) {
  t = clamp(t, 0.0, 1.0) * 4.0;
  vec3 k[5] = vec3[5](vec3(0.267, 0.005, 0.329), vec3(0.231, 0.322, 0.545),
                      vec3(0.129, 0.569, 0.549), vec3(0.369, 0.788, 0.384), vec3(0.992, 0.906, 0.145));
  int i = min(int(t), 3);
  return mix(k[i], k[i + 1], t - float(i));
}
// The scalar a false-colour view shows: the isolated channel, else luminance (Rec. 709).
float scalarOf(vec4 v, int channels) {
  if (isolate >= 1 && isolate <= 4) return v[min(isolate - 1, channels - 1)];
  if (channels == 1) return v.r;
  return dot(v.rgb, vec3(0.2126, 0.7152, 0.0722));
}
vec3 preview(vec4 v, int channels, int managed) {
  if (falseColor == 1) return viridis(finite(scalarOf(v, channels) * gain) / falseMax);
  vec3 rgb;
  if (isolate >= 1 && isolate <= 4) rgb = vec3(v[min(isolate - 1, channels - 1)]);
  else if (isolate == 5) rgb = vec3(scalarOf(v, channels));
  else for (int c = 0; c < 3; ++c) {
    int from = channels == 1 ? 0 : c;
    rgb[c] = from < channels ? v[from] : 0.0;
  }
  for (int c = 0; c < 3; ++c) {
    float e = finite(rgb[c] * gain);
    rgb[c] = clamp(managed == 1 ? lookup(e, c) : e, 0.0, 1.0);
  }
  return rgb;
}
void main() {
  vec2 p = (vec2(screen.x, 1.0 - screen.y) * canvasSize - pan) / zoom;  // image pixels, y down
  if (p.x < 0.0 || p.y < 0.0 || p.x >= sizeA.x || p.y >= sizeA.y) { color = vec4(0.0); return; }
  ivec2 px = ivec2(floor(p));
  vec4 a = texelFetch(imgA, px, 0);
  vec4 b = haveB == 1 ? texelFetch(imgB, px, 0) : a;
  bool showB = mode == 1 || (mode == 2 && p.x >= wipe * sizeA.x);
  if (mode == 3) {
    float d = 0.0;
    for (int c = 0; c < 4; ++c) if (c < channelsA) d += abs(finite(a[c]) - finite(b[c]));
    color = vec4(viridis(d / float(channelsA) / falseMax), 1.0);
    return;
  }
  vec3 rgb = showB ? preview(b, channelsB, colorB) : preview(a, channelsA, colorA);
  if (mode == 2 && abs(p.x - wipe * sizeA.x) < 0.75 / zoom) rgb = vec3(1.0);
  color = vec4(rgb, 1.0);
}`;

class Viewer {
  constructor(canvas) {
    this.canvas = canvas;
    const gl = this.gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL2');
    const shader = (type, src) => {
      const s = gl.createShader(type);
      gl.shaderSource(s, src);
      gl.compileShader(s);
      if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
      return s;
    };
    const prog = this.program = gl.createProgram();
    gl.attachShader(prog, shader(gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(prog, shader(gl.FRAGMENT_SHADER, FRAGMENT));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    gl.useProgram(prog);
    const quad = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, quad);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([0, 0, 1, 0, 0, 1, 1, 1]), gl.STATIC_DRAW);
    const loc = gl.getAttribLocation(prog, 'corner');
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
    this.textures = { imgA: gl.createTexture(), imgB: gl.createTexture(), lut: gl.createTexture() };
    this.a = null; this.b = null;
    this.state = { mode: 0, isolate: 0, falseColor: 0, gain: 1, falseMax: 1, wipe: 0.5, zoom: 1, pan: [0, 0] };
    new ResizeObserver(() => this.draw()).observe(canvas);
  }
  upload(unit, name, image) {
    const gl = this.gl;
    const formats = [null, [gl.R32F, gl.RED], [gl.RG32F, gl.RG], [gl.RGB32F, gl.RGB], [gl.RGBA32F, gl.RGBA]];
    const [internal, format] = formats[image.channels.length];
    gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(gl.TEXTURE_2D, this.textures[name]);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, internal, image.width, image.height, 0, format, gl.FLOAT, image.data);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    gl.uniform1i(gl.getUniformLocation(this.program, name), unit);
  }
  setLut(table) {  // 3 planes of 65536 → a 256 × 256 RGB texture
    const rgb = new Float32Array(65536 * 3);
    for (let i = 0; i < 65536; ++i) for (let c = 0; c < 3; ++c) rgb[i * 3 + c] = table[c * 65536 + i];
    this.upload(2, 'lut', { width: 256, height: 256, channels: ['R', 'G', 'B'], data: rgb });
    this.draw();
  }
  setA(image) { const first = !this.a; this.a = image; this.upload(0, 'imgA', image); if (first) this.fit(); this.draw(); }
  setB(image) { this.b = image; if (image) this.upload(1, 'imgB', image); this.draw(); }
  fit() {
    if (!this.a) return;
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    const zoom = Math.max(1 / 16, Math.min(w / this.a.width, h / this.a.height));
    this.state.zoom = zoom;
    this.state.pan = [(w - this.a.width * zoom) / 2, (h - this.a.height * zoom) / 2];
    this.draw();
  }
  // The image pixel under a canvas position (CSS pixels), or null outside.
  pixelAt(cx, cy) {
    if (!this.a) return null;
    const x = Math.floor((cx - this.state.pan[0]) / this.state.zoom);
    const y = Math.floor((cy - this.state.pan[1]) / this.state.zoom);
    return x >= 0 && y >= 0 && x < this.a.width && y < this.a.height ? [x, y] : null;
  }
  draw() {
    const gl = this.gl, c = this.canvas, s = this.state;
    const w = c.clientWidth, h = c.clientHeight;
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    if (!this.a) return;
    const u = (n) => gl.getUniformLocation(this.program, n);
    const b = this.b && this.b.width === this.a.width && this.b.height === this.a.height ? this.b : null;
    gl.uniform1i(u('channelsA'), this.a.channels.length);
    gl.uniform1i(u('channelsB'), b ? b.channels.length : this.a.channels.length);
    gl.uniform1i(u('haveB'), b ? 1 : 0);
    gl.uniform1i(u('colorA'), this.a.color && this.lutReady ? 1 : 0);
    gl.uniform1i(u('colorB'), b && b.color && this.lutReady ? 1 : 0);
    gl.uniform1i(u('mode'), b ? s.mode : 0);
    gl.uniform1i(u('isolate'), s.isolate);
    gl.uniform1i(u('falseColor'), s.falseColor);
    gl.uniform1f(u('gain'), s.gain);
    gl.uniform1f(u('falseMax'), Math.max(s.falseMax, 1e-20));
    gl.uniform1f(u('wipe'), s.wipe);
    gl.uniform2f(u('canvasSize'), w, h);
    gl.uniform2f(u('sizeA'), this.a.width, this.a.height);
    gl.uniform2f(u('pan'), s.pan[0], s.pan[1]);
    gl.uniform1f(u('zoom'), s.zoom);
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
  }
}

// ---------------------------------------------------------------------------------------------
// The page's state

const page = window.workbench = {  // window.workbench: for scripts and the browser test
  viewer: null,
  timings: [],            // per finished change: when it was sent, run, fetched and drawn (ms)
  pending: null,
  params: null,           // GET /api/params
  initial: new Map(),     // "cvar:NAME" / "set:PASS.PARAM" → the value at load, to step back
  generation: 0,          // the newest change this page asked for
  shown: { a: null, b: null },
  history: [],
};

function setStatus(text, error = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', error);
}

function formatValue(v) { return typeof v === 'number' && !Number.isInteger(v) ? +v.toPrecision(4) : v; }

// One control for a parameter or cvar, made from its spec.
function control(key, spec, onChange) {
  const div = document.createElement('div');
  div.className = 'param';
  div.dataset.key = key;
  const label = document.createElement('label');
  label.textContent = spec.label;
  label.title = spec.doc || '';
  div.append(label);
  let input, read;
  const value = spec.value ?? spec.default;
  if (spec.type === 'bool' || typeof value === 'boolean') {
    input = document.createElement('input');
    input.type = 'checkbox';
    input.checked = value === true || value === 1;
    read = () => (typeof value === 'number' ? (input.checked ? 1 : 0) : input.checked);
    div.append(input);
  } else if (spec.choices && spec.choices.length) {
    input = document.createElement('select');
    for (const c of spec.choices) input.append(new Option(c, c));
    input.value = value;
    read = () => input.value;
    div.append(input);
  } else if (spec.type === 'int' || spec.type === 'float' || typeof value === 'number') {
    const integer = spec.type === 'int' || (spec.type === undefined && Number.isInteger(value));
    input = document.createElement('input');
    input.type = 'number';
    input.step = integer ? 1 : 'any';
    if (spec.min !== undefined) input.min = spec.min;
    if (spec.max !== undefined) input.max = spec.max;
    input.value = value;
    div.append(input);
    if (spec.min !== undefined && spec.max !== undefined && spec.max - spec.min <= 1e4) {
      const range = document.createElement('input');
      range.type = 'range';
      range.min = spec.min; range.max = spec.max;
      range.step = integer ? 1 : (spec.max - spec.min) / 200;
      range.value = value;
      range.setAttribute('aria-label', spec.label);
      range.addEventListener('input', () => { input.value = range.value; });
      range.addEventListener('change', () => { input.value = range.value; input.dispatchEvent(new Event('change')); });
      input.addEventListener('input', () => { range.value = input.value; });
      div.append(range);
    }
    read = () => (integer ? parseInt(input.value, 10) : parseFloat(input.value));
  } else {
    input = document.createElement('input');
    input.value = value ?? '';
    read = () => input.value;
    div.append(input);
  }
  input.setAttribute('aria-label', spec.label);
  input.addEventListener('change', () => onChange(read(), div));
  if (spec.doc) {
    const doc = document.createElement('div');
    doc.className = 'doc';
    doc.textContent = spec.doc + (spec.default !== undefined ? ` (default ${spec.default})` : '');
    div.append(doc);
  }
  return div;
}

async function change(body, key, div) {
  try {
    const sent = performance.now();
    // The shown buffers go with every change: the run hands back only those (on a GPU each
    // buffer handed back is a copy to the host).
    const show = [page.shown.a, page.shown.b].filter(Boolean);
    const res = await api('/api/params?wait=0', { method: 'PUT', body: JSON.stringify({ ...body, show }) });
    const r = await res.json();
    page.pending = { generation: r.generation, sent };
    page.generation = Math.max(page.generation, r.generation);
    if (div) div.classList.add('changed');
    setStatus(`running (change ${r.generation})…`);
  } catch (e) {
    setStatus(e.message, true);
  }
}

function buildControls(params) {
  const cvars = $('cvars');
  cvars.textContent = '';
  for (const c of params.cvars.filter((c) => c.inChain && c.emulated !== false)) {
    const key = `cvar:${c.name}`;
    if (!page.initial.has(key)) page.initial.set(key, c.value);
    cvars.append(control(key, { ...c, label: c.name }, (v, div) => change({ cvars: { [c.name]: v } }, key, div)));
  }
  const passes = $('passes');
  passes.textContent = '';
  for (const p of params.passes) {
    const details = document.createElement('details');
    const summary = document.createElement('summary');
    summary.textContent = `${p.name} (${p.type})`;
    details.append(summary);
    for (const spec of p.params) {
      const key = `set:${p.name}.${spec.name}`;
      if (!page.initial.has(key)) page.initial.set(key, spec.value);
      details.append(control(key, { ...spec, label: spec.name },
        (v, div) => change({ set: { [`${p.name}.${spec.name}`]: v } }, key, div)));
    }
    passes.append(details);
  }
  const frame = $('frame');
  frame.min = 0;
  frame.max = params.frames.length - 1;
  frame.value = Math.max(0, params.frames.indexOf(params.frame));
  $('frame-label').textContent = `frame ${params.frame}`;
  $('frame-row').hidden = params.frames.length < 2;
}

// ---------------------------------------------------------------------------------------------
// The chain as a graph: columns by depth, output ports clickable

function buildGraph(plan) {
  const svgNS = 'http://www.w3.org/2000/svg';
  const el = (tag, attrs, parent) => {
    const e = document.createElementNS(svgNS, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    parent.append(e);
    return e;
  };
  const depth = new Map();
  const captures = new Set();
  for (const s of plan.steps) {
    let d = 1;
    for (const src of Object.values(s.inputs)) {
      if (src.startsWith('capture:')) captures.add(src.slice(8));
      else d = Math.max(d, (depth.get(src.split('.')[0]) ?? 0) + 1);
    }
    depth.set(s.name, d);
  }
  const columns = [[...captures].map((c) => ({ name: c, capture: true, outputs: [c] }))];
  for (const s of plan.steps) (columns[depth.get(s.name)] ||= []).push(s);
  const culled = (plan.culled || []).map((c) => ({ name: c.name, type: c.type, culled: true, outputs: [], reason: c.reason }));
  if (culled.length) columns.push(culled);
  const colW = 150, rowH = 12, pad = 8;
  const pos = new Map();
  let height = 0;
  columns.forEach((col, ci) => {
    let y = pad;
    for (const n of col || []) {
      const h = 30 + rowH * n.outputs.length;
      pos.set(n.name, { x: pad + ci * colW, y, h });
      y += h + pad;
    }
    height = Math.max(height, y);
  });
  const svg = document.createElementNS(svgNS, 'svg');
  svg.setAttribute('viewBox', `0 0 ${pad + columns.length * colW} ${height}`);
  svg.setAttribute('width', pad + columns.length * colW);  // natural size: the panel scrolls
  svg.setAttribute('height', height);
  for (const s of plan.steps) {
    const to = pos.get(s.name);
    for (const src of Object.values(s.inputs)) {
      const from = pos.get(src.startsWith('capture:') ? src.slice(8) : src.split('.')[0]);
      if (!from) continue;
      const x0 = from.x + colW - 20, y0 = from.y + 12, x1 = to.x, y1 = to.y + 12;
      el('path', { d: `M${x0},${y0} C${x0 + 20},${y0} ${x1 - 20},${y1} ${x1},${y1}` }, svg);
    }
  }
  for (const col of columns) for (const n of col || []) {
    const p = pos.get(n.name);
    const time = plan.times?.[n.name];
    const g = el('g', { class: `node${n.capture ? ' capture' : ''}${n.device === 'cuda' ? ' gpu' : ''}${n.culled ? ' culled' : ''}${time?.reused ? ' reused' : ''}`, 'data-pass': n.name }, svg);
    el('rect', { x: p.x, y: p.y, width: colW - 20, height: p.h }, g);
    el('text', { x: p.x + 4, y: p.y + 12, 'font-weight': 'bold' }, g).textContent = n.name;
    const sub = n.capture ? 'capture' : n.culled ? `culled: ${n.reason}` : `${n.device}${time ? ` · ${time.reused ? 'reused' : time.ms.toFixed(1) + ' ms'}` : ''}`;
    const t = el('text', { x: p.x + 4, y: p.y + 24, class: 'time' }, g);
    t.textContent = sub.length > 28 ? sub.slice(0, 27) + '…' : sub;
    if (n.culled) { const title = el('title', {}, g); title.textContent = n.reason; }
    n.outputs.forEach((o, i) => {
      const name = n.capture ? o : `${n.name}.${o}`;
      const port = el('text', { x: p.x + 10, y: p.y + 36 + i * rowH, class: 'port', 'data-buffer': name }, g);
      port.textContent = n.capture ? '▸ show' : `▸ ${o}`;
      port.addEventListener('click', (ev) => selectBuffer(ev.shiftKey ? 'b' : 'a', name));
    });
  }
  $('graph').replaceChildren(svg);
  markShownPorts();
}

function markShownPorts() {
  for (const p of document.querySelectorAll('#graph .port'))
    p.classList.toggle('shown', p.dataset.buffer === page.shown.a || p.dataset.buffer === page.shown.b);
}

// ---------------------------------------------------------------------------------------------
// Report, errors, history

function buildReport(report) {
  const body = $('report').tBodies[0];
  body.textContent = '';
  if (!report) return;
  for (const p of report.passes) {
    const tr = body.insertRow();
    tr.className = p.reused ? 'reused' : '';
    tr.insertCell().textContent = p.name;
    const ms = tr.insertCell();
    ms.className = 'num';
    ms.textContent = p.reused ? '–' : (p.seconds * 1e3).toFixed(2);
    tr.insertCell().textContent = p.reused ? 'reused' : '';
  }
  $('timing').textContent = `frame ${report.frame}: ${report.wallMs.toFixed(1)} ms wall, ` +
    `${report.executedSteps} run, ${report.reusedSteps} reused`;
  // The error figures: one row per error measure.
  const table = $('errors');
  table.textContent = '';
  const figures = ['rmse', 'relMse', 'bias'];
  const head = table.createTHead().insertRow();
  for (const h of ['measure', ...figures]) head.append(Object.assign(document.createElement('th'), { textContent: h }));
  const rows = table.createTBody();
  for (const [pass, f] of Object.entries(report.errors || {})) {
    const tr = rows.insertRow();
    tr.insertCell().textContent = pass;
    for (const k of figures) {
      const c = tr.insertCell();
      c.className = 'num';
      c.textContent = f[k] === undefined ? '' : f[k].toPrecision(3);
    }
  }
}

// The error taken apart, as bench does it: converged, screen-space limit, one bounce, full.
async function breakdown() {
  const out = $('breakdown-text');
  out.textContent = 'taking the error apart…';
  try {
    const r = await getJSON(`/api/breakdown?rays=${+$('breakdown-rays').value}`);
    out.textContent = r.errors.filter((e) => e.text).map((e) => `${e.name}:\n${e.text}`).join('\n') ||
      'no error measure here compares a screen-space pass with a truth layer';
    out.textContent += `\n(${r.rays} rays, ${(r.ms / 1000).toFixed(1)} s)`;
  } catch (e) {
    out.textContent = e.message;
  }
}

// The settings ({cvars: {name: value}, set: {name: value}}) as NAME=VALUE words.
function settingsLabel(settings) {
  const all = [...Object.entries(settings.cvars), ...Object.entries(settings.set)]
    .map(([name, value]) => `${name}=${typeof value === 'string' ? value : JSON.stringify(value)}`);
  return all.length ? all.join(' ') : 'as loaded';
}

function pushHistory(report, params) {
  const entry = { settings: params.settings, frame: params.frame, ms: report.wallMs, errors: report.errors };
  const label = settingsLabel(entry.settings);
  if (page.history.length && page.history[0].label === label) return;
  entry.label = label;
  page.history.unshift(entry);
  page.history.length = Math.min(page.history.length, 20);
  const list = $('history');
  list.textContent = '';
  for (const h of page.history) {
    const li = document.createElement('li');
    const err = Object.entries(h.errors || {}).map(([p, f]) => `${p} RMSE ${f.rmse?.toPrecision(3)}`).join(', ');
    li.textContent = `${h.label} — ${h.ms.toFixed(0)} ms${err ? ', ' + err : ''}`;
    li.title = 'click to go back to these settings';
    li.addEventListener('click', () => restore(h));
    list.append(li);
  }
}

// Back to a history entry: its settings, and the values at load for what it did not set.
function restore(entry) {
  const body = { cvars: {}, set: {} };
  for (const [key, value] of page.initial) {
    const [kind, name] = [key.slice(0, key.indexOf(':')), key.slice(key.indexOf(':') + 1)];
    body[kind === 'cvar' ? 'cvars' : 'set'][name] = value;
  }
  Object.assign(body.cvars, entry.settings.cvars);
  Object.assign(body.set, entry.settings.set);
  change(body);
}

// ---------------------------------------------------------------------------------------------
// Buffers

async function selectBuffer(which, name) {
  page.shown[which] = name;
  $(`buffer-${which}`).value = name;
  markShownPorts();
  await loadShown(which);
}

async function loadShown(which) {
  const name = page.shown[which];
  if (!name) return;
  try {
    const start = performance.now();
    const image = await fetchBuffer(name);
    if (page.shown[which] !== name) return;  // another was chosen meanwhile
    const fetched = performance.now();
    if (which === 'a') page.viewer.setA(image); else page.viewer.setB(image);
    page.viewer.gl.finish();
    if (which === 'a' && page.pending && image.generation >= page.pending.generation) {
      page.timings.push({ ...page.pending, fetchStart: start, fetched, drawn: performance.now(), bytes: image.data.byteLength });
      page.pending = null;
    }
  } catch (e) {
    setStatus(`${name}: ${e.message}`, true);
  }
}

function probe(ev) {
  const v = page.viewer;
  const rect = v.canvas.getBoundingClientRect();
  const px = v.pixelAt(ev.clientX - rect.left, ev.clientY - rect.top);
  if (!px) return;
  const lines = [`pixel ${px[0]}, ${px[1]}`];
  for (const img of [v.a, v.b]) {
    if (!img || px[0] >= img.width || px[1] >= img.height) continue;
    const n = img.channels.length, i = (px[1] * img.width + px[0]) * n;
    const values = img.channels.map((c, k) => `${c}=${img.data[i + k].toPrecision(9)}`);
    lines.push(`${img.name}: ${values.join(' ')}`);
  }
  $('probe').textContent = lines.join('\n');
  $('probe').dataset.x = px[0];
  $('probe').dataset.y = px[1];
}

// ---------------------------------------------------------------------------------------------
// Everything after a run

// A capture buffer or truth layer does not change with the settings; a pass output does.
const isPassOutput = (name) => name && name.includes('.') && !name.startsWith('Truth.');

async function refresh() {
  const images = Promise.all(['a', 'b'].map((w) => (isPassOutput(page.shown[w]) || !page.viewer[w] ? loadShown(w) : null)));
  const [params, plan, report] = await Promise.all([getJSON('/api/params'), getJSON('/api/graph'), getJSON('/api/report')]);
  page.params = params;
  buildGraph(plan);
  buildReport(report);
  $('frame-label').textContent = `frame ${params.frame}`;
  if (report) pushHistory(report, params);
  await images;
  return report;
}

function listen() {
  const events = new EventSource('/api/events');
  events.onmessage = async (msg) => {
    const e = JSON.parse(msg.data);
    if (e.type === 'pass') {
      $('progress').max = e.total;
      $('progress').value = e.done;
      setStatus(`change ${e.generation}: ${e.pass} (${e.done}/${e.total})`);
    } else if (e.type === 'frame' && e.generation >= page.generation) {
      if (page.pending && e.generation >= page.pending.generation) { page.pending.run = e.ms; page.pending.event = performance.now(); }
      await refresh();
      setStatus(`change ${e.generation} done in ${e.ms.toFixed(1)} ms`);
      if ($('breakdown-auto').checked) breakdown();
      document.body.dataset.generation = e.generation;
    } else if (e.type === 'error') {
      setStatus(e.message, true);
    } else if (e.type === 'cancelled') {
      setStatus(`change ${e.generation} replaced by a newer one`);
    }
  };
}

function download(name, text, type) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
}

async function main() {
  const viewer = page.viewer = new Viewer($('canvas'));
  const [params, buffers, displays] = await Promise.all([getJSON('/api/params'), getJSON('/api/buffers'), getJSON('/api/displays')]);
  page.params = params;
  buildControls(params);

  const all = [...buffers.passes, ...buffers.capture, ...buffers.truth];
  for (const which of ['a', 'b']) {
    const sel = $(`buffer-${which}`);
    if (which === 'b') sel.append(new Option('(none)', ''));
    for (const n of all) sel.append(new Option(n, n));
    sel.addEventListener('change', () => selectBuffer(which, sel.value || null));
  }
  // A and B: what the config's first error measure compares (a pass output and its truth),
  // else the last pass's first output alone.
  const plan = await getJSON('/api/graph');
  const measure = plan.steps.find((s) => s.type === 'error_measure');
  const source = (ref) => (ref && ref.startsWith('capture:') ? ref.slice(8) : ref);
  page.shown.a = measure ? source(measure.inputs.source) : buffers.passes[buffers.passes.length - 1];
  page.shown.b = measure ? source(measure.inputs.reference) : null;
  $('buffer-a').value = page.shown.a;
  $('buffer-b').value = page.shown.b || '';

  const display = displays.displays.find((d) => d.display === displays.defaultDisplay) || displays.displays[0];
  for (const v of display?.views || []) $('view').append(new Option(v, v));
  $('view').value = display?.defaultView || '';
  const loadLut = async () => {
    try {
      const table = new Float32Array(await (await api(`/api/lut?view=${encodeURIComponent($('view').value)}`)).arrayBuffer());
      viewer.setLut(table);
      viewer.lutReady = true;
    } catch (e) {
      viewer.lutReady = false;
      setStatus(`view ${$('view').value}: ${e.message}`, true);
    }
    viewer.draw();
  };
  $('view').addEventListener('change', loadLut);
  await loadLut();

  // Viewer controls: nothing here asks the server anything.
  const state = viewer.state;
  const modes = { a: 0, b: 1, wipe: 2, diff: 3 };
  $('mode').addEventListener('change', () => { state.mode = modes[$('mode').value]; viewer.draw(); });
  $('exposure').addEventListener('input', () => {
    state.gain = 2 ** +$('exposure').value;
    $('exposure-value').textContent = (+$('exposure').value).toFixed(1);
    viewer.draw();
  });
  $('channel').addEventListener('change', () => { state.isolate = +$('channel').value; viewer.draw(); });
  const scaleBar = () => {
    $('scale-bar').hidden = !(state.falseColor || state.mode === 3);
    $('scale-max').textContent = (+$('false-max').value).toPrecision(3);
  };
  $('false-color').addEventListener('change', () => { state.falseColor = $('false-color').checked ? 1 : 0; scaleBar(); viewer.draw(); });
  $('false-max').addEventListener('input', () => { state.falseMax = +$('false-max').value; scaleBar(); viewer.draw(); });
  $('mode').addEventListener('change', scaleBar);
  // The scale's top: the 99th percentile of what is shown in false colour (the isolated channel
  // or luminance, exposed) or of |A − B|, as compare's heat map picks its scale.
  const autoMax = () => {
    const a = viewer.a, b = viewer.b;
    if (!a) return;
    const n = a.channels.length, values = [];
    const diff = state.mode === 3 && b && b.width === a.width && b.height === a.height;
    const step = Math.max(1, Math.floor(a.width * a.height / 65536));  // a sample is enough
    for (let p = 0; p < a.width * a.height; p += step) {
      let v = 0;
      if (diff) {
        for (let c = 0; c < n; ++c) v += Math.abs(a.data[p * n + c] - b.data[p * b.channels.length + Math.min(c, b.channels.length - 1)]);
        v /= n;
      } else if (state.isolate >= 1 && state.isolate <= 4) {
        v = a.data[p * n + Math.min(state.isolate - 1, n - 1)] * state.gain;
      } else {
        v = (n === 1 ? a.data[p] : 0.2126 * a.data[p * n] + 0.7152 * a.data[p * n + 1] + 0.0722 * a.data[p * n + 2]) * state.gain;
      }
      if (Number.isFinite(v)) values.push(v);
    }
    values.sort((x, y) => x - y);
    const top = values.length ? values[Math.floor(0.99 * (values.length - 1))] : 1;
    $('false-max').value = +(top > 0 ? top : 1).toPrecision(3);
    state.falseMax = +$('false-max').value;
    scaleBar();
    viewer.draw();
  };
  $('auto-max').addEventListener('click', autoMax);
  $('mode').addEventListener('change', () => { if (state.mode === 3) autoMax(); });
  $('false-color').addEventListener('change', () => { if (state.falseColor) autoMax(); });
  $('wipe').addEventListener('input', () => { state.wipe = +$('wipe').value; viewer.draw(); });
  const flip = () => {
    [page.shown.a, page.shown.b] = [page.shown.b || page.shown.a, page.shown.a];
    [viewer.a, viewer.b] = [viewer.b || viewer.a, viewer.a];
    $('buffer-a').value = page.shown.a;
    $('buffer-b').value = page.shown.b || '';
    if (viewer.a) viewer.upload(0, 'imgA', viewer.a);
    if (viewer.b) viewer.upload(1, 'imgB', viewer.b);
    markShownPorts();
    viewer.draw();
  };
  $('flip').addEventListener('click', flip);
  document.addEventListener('keydown', (e) => { if (e.key === 'f' && e.target.tagName !== 'INPUT') flip(); });
  $('fit').addEventListener('click', () => viewer.fit());
  const canvas = $('canvas');
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const rect = canvas.getBoundingClientRect();
    const cx = e.clientX - rect.left, cy = e.clientY - rect.top;
    const k = e.deltaY < 0 ? 1.25 : 0.8;
    state.pan = [cx - (cx - state.pan[0]) * k, cy - (cy - state.pan[1]) * k];
    state.zoom *= k;
    viewer.draw();
  }, { passive: false });
  let drag = null;
  canvas.addEventListener('mousedown', (e) => { drag = [e.clientX, e.clientY]; });
  window.addEventListener('mouseup', () => { drag = null; });
  canvas.addEventListener('mousemove', (e) => {
    if (drag) {
      state.pan = [state.pan[0] + e.clientX - drag[0], state.pan[1] + e.clientY - drag[1]];
      drag = [e.clientX, e.clientY];
      viewer.draw();
    }
    probe(e);
  });

  $('breakdown').addEventListener('click', breakdown);
  $('frame').addEventListener('change', () => change({ frame: page.params.frames[+$('frame').value] }));
  $('export-config').addEventListener('click', async () => {
    const x = await getJSON('/api/export');
    download('framepass_config.json', JSON.stringify(x.config, null, 2) + '\n', 'application/json');
    $('export-note').textContent = 'run it with: framepass run framepass_config.json -o out';
  });
  $('export-ini').addEventListener('click', async () => {
    const x = await getJSON('/api/export');
    download('framepass_cvars.ini', x.ini, 'text/plain');
  });
  $('tev-push').addEventListener('click', async () => {
    try {
      const names = [page.shown.a, page.shown.b].filter(Boolean);
      const r = await (await api('/api/tev', { method: 'POST', body: JSON.stringify({ host: $('tev-host').value, buffers: names }) })).json();
      $('export-note').textContent = `sent to tev: ${r.images.join(', ')}`;
    } catch (e) {
      $('export-note').textContent = `tev: ${e.message}`;
    }
  });

  listen();
  const report = await refresh();
  setStatus(report ? 'ready' : 'running the first frame…');
  if (report) document.body.dataset.generation = report.generation;
}

main().catch((e) => setStatus(e.message, true));
