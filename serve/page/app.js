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

// Where a canvas fragment falls on the image (image pixels, y down) and where the wipe is: the
// one placement of FRAGMENT's canvas path and of BLIT.
const PLACE = `
uniform vec2 canvasSize, sizeA, pan; uniform float zoom, wipe;
vec2 imagePoint() { return (vec2(screen.x, 1.0 - screen.y) * canvasSize - pan) / zoom; }
bool outsideImage(vec2 p) { return p.x < 0.0 || p.y < 0.0 || p.x >= sizeA.x || p.y >= sizeA.y; }
bool rightOfWipe(vec2 p) { return p.x >= wipe * sizeA.x; }
bool onWipeLine(vec2 p) { return abs(p.x - wipe * sizeA.x) < 0.75 / zoom; }`;

// The display maths of the library's display pass (passes/display/DisplayKernel.h): exposure,
// the channel mapping of a preview, the baked view looked up between neighbouring halves, clamp.
// What a draw shows is compiled in (#define, see Viewer.programFor): a software renderer runs
// every line of a shader for every pixel, taken or not, so each view gets only its own lines.
const FRAGMENT = `
precision highp float; precision highp int; precision highp usampler2D; precision highp sampler3D;
in vec2 screen;
layout(location = 0) out vec4 color;
layout(location = 1) out vec4 pictureB;
uniform sampler2D imgA, imgB, lut;
uniform sampler3D cube;
uniform int channelsA, channelsB, isolate;
uniform float cubeLog2Min, cubeLog2Max;
uniform float gain, falseMax;
${PLACE}

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
// Unreal's film view: the server's table over log2 of each channel (/api/film-cube), trilinear.
vec3 filmLookup(vec3 v) {
  int n = textureSize(cube, 0).x;
  vec3 u = clamp((log2(max(v, vec3(exp2(cubeLog2Min)))) - cubeLog2Min) / (cubeLog2Max - cubeLog2Min), 0.0, 1.0) * float(n - 1);
  ivec3 i = min(ivec3(floor(u)), ivec3(n - 2));
  vec3 f = u - vec3(i);
  vec3 c00 = mix(texelFetch(cube, i, 0).rgb, texelFetch(cube, i + ivec3(1, 0, 0), 0).rgb, f.x);
  vec3 c10 = mix(texelFetch(cube, i + ivec3(0, 1, 0), 0).rgb, texelFetch(cube, i + ivec3(1, 1, 0), 0).rgb, f.x);
  vec3 c01 = mix(texelFetch(cube, i + ivec3(0, 0, 1), 0).rgb, texelFetch(cube, i + ivec3(1, 0, 1), 0).rgb, f.x);
  vec3 c11 = mix(texelFetch(cube, i + ivec3(0, 1, 1), 0).rgb, texelFetch(cube, i + ivec3(1, 1, 1), 0).rgb, f.x);
  return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}
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
vec3 preview(vec4 v, int channels, bool managed) {
#if FALSE_COLOR
  return viridis(finite(scalarOf(v, channels) * gain) / falseMax);
#else
  vec3 rgb;
  if (isolate >= 1 && isolate <= 4) rgb = vec3(v[min(isolate - 1, channels - 1)]);
  else if (isolate == 5) rgb = vec3(scalarOf(v, channels));
  else for (int c = 0; c < 3; ++c) {
    int from = channels == 1 ? 0 : c;
    rgb[c] = from < channels ? v[from] : 0.0;
  }
  for (int c = 0; c < 3; ++c) rgb[c] = finite(rgb[c] * gain);
  if (!managed) return clamp(rgb, 0.0, 1.0);
#if FILM
  return clamp(filmLookup(rgb), 0.0, 1.0);
#else
  for (int c = 0; c < 3; ++c) rgb[c] = clamp(lookup(rgb[c], c), 0.0, 1.0);
  return rgb;
#endif
#endif
}
vec4 difference(vec4 a, vec4 b) {
  float d = 0.0;
  for (int c = 0; c < 4; ++c) if (c < channelsA) d += abs(finite(a[c]) - finite(b[c]));
  return vec4(viridis(d / float(channelsA) / falseMax), 1.0);
}
void main() {
#if TO_IMAGE
  // One fragment an image pixel, into the two images the blit places on the canvas: A's
  // picture (or the difference) and B's where it is shown.
  ivec2 px = ivec2(int(gl_FragCoord.x), int(sizeA.y) - 1 - int(gl_FragCoord.y));
#else
  vec2 p = imagePoint();
  if (outsideImage(p)) { color = vec4(0.0); return; }
  ivec2 px = ivec2(floor(p));
#endif
  vec4 a = texelFetch(imgA, px, 0);
#if MODE == 0
  color = vec4(preview(a, channelsA, COLOR_A == 1), 1.0);
#else
  vec4 b = texelFetch(imgB, px, 0);
#if MODE == 3
  color = difference(a, b);
#elif TO_IMAGE
  color = vec4(preview(a, channelsA, COLOR_A == 1), 1.0);
  pictureB = vec4(preview(b, channelsB, COLOR_B == 1), 1.0);
#else
  bool showB = MODE == 1 || rightOfWipe(p);
  vec3 rgb = showB ? preview(b, channelsB, COLOR_B == 1) : preview(a, channelsA, COLOR_A == 1);
  if (MODE == 2 && onWipeLine(p)) rgb = vec3(1.0);
  color = vec4(rgb, 1.0);
#endif
#endif
}`;

// Places the images FRAGMENT drew at image resolution on the canvas: zoom, pan, the wipe and its
// line, as FRAGMENT's canvas path does.
const BLIT = `
precision highp float;
in vec2 screen; out vec4 color;
uniform sampler2D shownA, shownB;
uniform int mode;
${PLACE}
void main() {
  vec2 p = imagePoint();
  if (outsideImage(p)) { color = vec4(0.0); return; }
  ivec2 px = ivec2(floor(p));
  px.y = int(sizeA.y) - 1 - px.y;  // the images are stored bottom row first
  bool showB = mode == 1 || (mode == 2 && rightOfWipe(p));
  color = showB ? texelFetch(shownB, px, 0) : texelFetch(shownA, px, 0);
  if (mode == 2 && onWipeLine(p)) color = vec4(1.0);
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
    const program = (fragment) => {
      const prog = gl.createProgram();
      gl.attachShader(prog, shader(gl.VERTEX_SHADER, VERTEX));
      gl.attachShader(prog, shader(gl.FRAGMENT_SHADER, `#version 300 es\n${fragment}`));
      gl.bindAttribLocation(prog, 0, 'corner');
      gl.linkProgram(prog);
      if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
      return prog;
    };
    // FRAGMENT's programs by what they show, made when first drawn.
    this.programs = new Map();
    this.programFor = (defines) => {
      const key = JSON.stringify(defines);
      if (!this.programs.has(key)) {
        const prog = program(Object.entries(defines).map(([k, v]) => `#define ${k} ${+v}\n`).join('') + FRAGMENT);
        gl.useProgram(prog);
        for (const [name, unit] of [['imgA', 0], ['imgB', 1], ['lut', 2], ['cube', 3]])
          gl.uniform1i(gl.getUniformLocation(prog, name), unit);
        this.programs.set(key, prog);
      }
      return this.programs.get(key);
    };
    this.cubeRange = [0, 1];
    this.blit = program(BLIT);
    const quad = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, quad);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([0, 0, 1, 0, 0, 1, 1, 1]), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
    // The pictures at image resolution (8 bits, as the canvas keeps them) and their framebuffer.
    this.shown = { key: null, width: 0, height: 0, a: gl.createTexture(), b: gl.createTexture(), fbo: gl.createFramebuffer() };
    gl.useProgram(this.blit);
    gl.uniform1i(gl.getUniformLocation(this.blit, 'shownA'), 4);
    gl.uniform1i(gl.getUniformLocation(this.blit, 'shownB'), 5);
    this.textures = { imgA: gl.createTexture(), imgB: gl.createTexture(), lut: gl.createTexture(), cube: gl.createTexture() };
    this.uploads = 0;  // counts uploads: a picture drawn from older images is drawn again
    this.perImagePixel = true;  // false: FRAGMENT once a canvas pixel always (the browser test compares)
    // The film table's unit from the start (a 3D sampler left on unit 0 with the images' 2D ones
    // would make every draw fail), holding one black entry until the film view is chosen.
    this.setFilmCube(new Float32Array(3), 1, 0, 1);
    this.a = null; this.b = null;
    this.state = { mode: 0, isolate: 0, falseColor: 0, film: 0, gain: 1, falseMax: 1, wipe: 0.5, zoom: 1, pan: [0, 0] };
    // Resized (the window, a panel): a fitted image is fitted again, a zoomed one keeps the
    // image point at the canvas's centre where it was.
    this.fitted = true;
    this.size = [canvas.clientWidth, canvas.clientHeight];
    const resized = () => {
      const w = canvas.clientWidth, h = canvas.clientHeight;
      if (w === this.size[0] && h === this.size[1]) return;
      if (this.fitted) this.fit();
      else this.state.pan = [this.state.pan[0] + (w - this.size[0]) / 2, this.state.pan[1] + (h - this.size[1]) / 2];
      this.size = [w, h];
      this.draw();
    };
    new ResizeObserver(resized).observe(canvas);
  }
  upload(unit, name, image) {
    const gl = this.gl;
    const formats = [null, [gl.R32F, gl.RED], [gl.RG32F, gl.RG], [gl.RGB32F, gl.RGB], [gl.RGBA32F, gl.RGBA]];
    const [internal, format] = formats[image.channels.length];
    this.uploads += 1;
    gl.activeTexture(gl.TEXTURE0 + unit);
    gl.bindTexture(gl.TEXTURE_2D, this.textures[name]);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage2D(gl.TEXTURE_2D, 0, internal, image.width, image.height, 0, format, gl.FLOAT, image.data);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
  }
  setLut(table) {  // 3 planes of 65536 → a 256 × 256 RGB texture
    const rgb = new Float32Array(65536 * 3);
    for (let i = 0; i < 65536; ++i) for (let c = 0; c < 3; ++c) rgb[i * 3 + c] = table[c * 65536 + i];
    this.upload(2, 'lut', { width: 256, height: 256, channels: ['R', 'G', 'B'], data: rgb });
    this.draw();
  }
  // Unreal's film view: size³ RGB entries (3 planes, entry r + size·g + size²·b) over log2 of
  // each channel from log2Min to log2Max.
  setFilmCube(table, size, log2Min, log2Max) {
    const gl = this.gl, n = size * size * size;
    this.uploads += 1;
    const rgb = new Float32Array(n * 3);
    for (let i = 0; i < n; ++i) for (let c = 0; c < 3; ++c) rgb[i * 3 + c] = table[c * n + i];
    gl.activeTexture(gl.TEXTURE3);
    gl.bindTexture(gl.TEXTURE_3D, this.textures.cube);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage3D(gl.TEXTURE_3D, 0, gl.RGB32F, size, size, size, 0, gl.RGB, gl.FLOAT, rgb);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_3D, p, gl.NEAREST);
    this.cubeRange = [log2Min, log2Max];
    if (this.a) this.draw();
  }
  setA(image) { const first = !this.a; this.a = image; this.upload(0, 'imgA', image); if (first) this.fit(); this.draw(); }
  setB(image) { this.b = image; if (image) this.upload(1, 'imgB', image); this.draw(); }
  fit() {
    if (!this.a) return;
    const w = this.canvas.clientWidth, h = this.canvas.clientHeight;
    const zoom = Math.max(1 / 16, Math.min(w / this.a.width, h / this.a.height));
    this.state.zoom = zoom;
    this.state.pan = [(w - this.a.width * zoom) / 2, (h - this.a.height * zoom) / 2];
    this.fitted = true;
    this.draw();
  }
  // Zoom by `k` about canvas point (cx, cy) (default: the centre); `to` sets the zoom instead.
  zoomBy(k, cx = this.canvas.clientWidth / 2, cy = this.canvas.clientHeight / 2, to = null) {
    const s = this.state;
    if (to !== null) k = to / s.zoom;
    s.pan = [cx - (cx - s.pan[0]) * k, cy - (cy - s.pan[1]) * k];
    s.zoom *= k;
    this.fitted = false;
    this.draw();
  }
  // The image pixel under a canvas position (CSS pixels), or null outside.
  pixelAt(cx, cy) {
    if (!this.a) return null;
    const [x, y] = this.imagePoint(cx, cy).map(Math.floor);
    return x >= 0 && y >= 0 && x < this.a.width && y < this.a.height ? [x, y] : null;
  }
  // A canvas position (CSS pixels) in image pixels, unrounded.
  imagePoint(cx, cy) {
    return [(cx - this.state.pan[0]) / this.state.zoom, (cy - this.state.pan[1]) / this.state.zoom];
  }
  // Where the image has fewer pixels than the canvas (a small capture, a fitted or zoomed-in view)
  // FRAGMENT runs once an image pixel into this.shown, again only when what it computes changes,
  // and BLIT places that on the canvas; otherwise FRAGMENT runs once a canvas pixel. With software
  // rendering FRAGMENT is what a draw costs (about 1 µs a pixel on SwiftShader).
  draw() {
    const gl = this.gl, c = this.canvas, s = this.state;
    const w = c.clientWidth, h = c.clientHeight;
    if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }
    if (!this.a || !this.perImagePixel || this.a.width * this.a.height > w * h) return this.drawPicture(w, h, false);
    const sh = this.shown, a = this.a;
    const key = JSON.stringify([this.uploads, !!this.b, a.color, this.b?.color, this.lutReady, s.mode, s.isolate, s.falseColor, s.film, s.gain, s.falseMax]);
    if (sh.key !== key || sh.width !== a.width || sh.height !== a.height) {
      if (sh.width !== a.width || sh.height !== a.height) {
        for (const [unit, t] of [[4, sh.a], [5, sh.b]]) {
          gl.activeTexture(gl.TEXTURE0 + unit);
          gl.bindTexture(gl.TEXTURE_2D, t);
          gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, a.width, a.height, 0, gl.RGBA, gl.UNSIGNED_BYTE, null);
          for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
        }
        gl.bindFramebuffer(gl.FRAMEBUFFER, sh.fbo);
        gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, sh.a, 0);
        gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT1, gl.TEXTURE_2D, sh.b, 0);
        sh.width = a.width;
        sh.height = a.height;
      }
      gl.bindFramebuffer(gl.FRAMEBUFFER, sh.fbo);
      this.drawPicture(a.width, a.height, true);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      sh.key = key;
    }
    gl.useProgram(this.blit);
    const u = (n) => gl.getUniformLocation(this.blit, n);
    gl.uniform1i(u('mode'), this.comparableB() ? s.mode : 0);
    gl.uniform1f(u('wipe'), s.wipe);
    gl.uniform2f(u('canvasSize'), w, h);
    gl.uniform2f(u('sizeA'), a.width, a.height);
    gl.uniform2f(u('pan'), s.pan[0], s.pan[1]);
    gl.uniform1f(u('zoom'), s.zoom);
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    if (this.onDraw) this.onDraw();
  }
  // B where it can be drawn beside A (the same size), else null.
  comparableB() {
    return this.b && this.b.width === this.a.width && this.b.height === this.a.height ? this.b : null;
  }
  // FRAGMENT over a w × h target: the canvas (toImage false) or this.shown's two images.
  drawPicture(w, h, toImage) {
    const gl = this.gl, s = this.state;
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    if (!this.a) return;
    const b = this.comparableB();
    const prog = this.programFor({
      TO_IMAGE: toImage, MODE: b ? s.mode : 0, FALSE_COLOR: s.falseColor, FILM: s.film,
      COLOR_A: this.a.color && this.lutReady, COLOR_B: !!b && b.color && this.lutReady,
    });
    gl.useProgram(prog);
    // B's picture is drawn (and written) only where it is shown.
    const withB = b && (s.mode === 1 || s.mode === 2);
    if (toImage) gl.drawBuffers([gl.COLOR_ATTACHMENT0, withB ? gl.COLOR_ATTACHMENT1 : gl.NONE]);
    const u = (n) => gl.getUniformLocation(prog, n);
    gl.uniform1i(u('channelsA'), this.a.channels.length);
    gl.uniform1i(u('channelsB'), b ? b.channels.length : this.a.channels.length);
    gl.uniform1i(u('isolate'), s.isolate);
    gl.uniform1f(u('gain'), s.gain);
    gl.uniform1f(u('falseMax'), Math.max(s.falseMax, 1e-20));
    gl.uniform1f(u('wipe'), s.wipe);
    gl.uniform1f(u('cubeLog2Min'), this.cubeRange[0]);
    gl.uniform1f(u('cubeLog2Max'), this.cubeRange[1]);
    gl.uniform2f(u('canvasSize'), w, h);
    gl.uniform2f(u('sizeA'), this.a.width, this.a.height);
    gl.uniform2f(u('pan'), s.pan[0], s.pan[1]);
    gl.uniform1f(u('zoom'), s.zoom);
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    if (!toImage && this.onDraw) this.onDraw();
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
  plan: null,             // GET /api/graph, as last drawn
  controlsBuilt: 0,       // how many times the controls were made (a change from older ones is dropped)
  snapshots: [],          // pinned images of A: {label, image}, newest first
  snapshotB: null,        // the snapshot shown as B, if one is
  rect: null,             // the statistics rectangle in image pixels [x0, y0, x1, y1), if any
  rectStats: null,        // its statistics (for scripts and the browser test)
  graphFit: true,         // the graph fitted to its panel, else at its natural size
  methodRuns: [],         // per finished run: {generation, label, methods}, newest first
};

function setStatus(text, error = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', error);
}

// An SVG element with these attributes, appended to `parent`.
const SVG_NS = 'http://www.w3.org/2000/svg';
function svgElement(tag, attrs, parent) {
  const e = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  parent.append(e);
  return e;
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
  // A control replaced (the settings read again after a reconnect) is dead: a typed value it
  // still held must not reach the server when the browser commits it on removal.
  const built = page.controlsBuilt;
  input.addEventListener('change', () => { if (built === page.controlsBuilt) onChange(read(), div); });
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
  page.controlsBuilt += 1;
  const cvars = $('cvars');
  cvars.textContent = '';
  for (const c of params.cvars.filter((c) => c.inChain && c.emulated !== false)) {
    const key = `cvar:${c.name}`;
    if (!page.initial.has(key)) page.initial.set(key, c.value);
    const div = control(key, { ...c, label: c.name }, (v, d) => change({ cvars: { [c.name]: v } }, key, d));
    div.append(Object.assign(document.createElement('div'), { className: 'shadow-note' }));
    cvars.append(div);
  }
  markShadowed(params);
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

// A cvar whose parameter the config's params (or a set) fix wherever it reaches does nothing:
// said beside its slider, with what wins.
function markShadowed(params) {
  for (const c of params.cvars) {
    const div = document.querySelector(`.param[data-key="cvar:${CSS.escape(c.name)}"]`);
    if (!div) continue;
    const note = div.querySelector('.shadow-note');
    div.classList.toggle('shadowed', !!c.shadowedBy);
    note.textContent = c.shadowedBy ? `no effect: ${c.shadowedBy.join(', ')} sets it and wins` : '';
  }
}

// ---------------------------------------------------------------------------------------------
// The chain as a graph: layered top to bottom (a pass below everything it reads), a layer
// wider than the panel wrapped onto more rows, each layer ordered by where its sources are (fewer
// crossings); every name fits its box; output ports clickable, marked colour or data.

function buildGraph(plan) {
  page.plan = plan;
  const el = svgElement;
  const sourceOf = (ref) => (ref.startsWith('capture:') ? 'capture:' : ref.split('.')[0]);
  const reads = plan.steps.flatMap((s) => Object.values(s.inputs)).filter((r) => r.startsWith('capture:'));
  const nodes = [];
  if (reads.length)
    nodes.push({ id: 'capture:', label: 'capture', capture: true, rank: 0, sources: [],
                 outputs: [...new Set(reads.map((r) => r.slice(8)))].sort() });
  const byId = new Map(nodes.map((n) => [n.id, n]));
  for (const s of plan.steps) {
    const sources = [...new Set(Object.values(s.inputs).map(sourceOf))];
    const rank = Math.max(1, ...sources.map((id) => (byId.get(id)?.rank ?? 0) + 1));
    const n = { ...s, id: s.name, label: s.name, sources, rank };
    nodes.push(n);
    byId.set(n.id, n);
  }
  const lastRank = Math.max(0, ...nodes.map((n) => n.rank)) + 1;
  for (const c of plan.culled || [])
    nodes.push({ id: c.name, label: c.name, culled: true, reason: c.reason, rank: lastRank, sources: [], outputs: [] });
  const subtitle = (n) => {
    if (n.capture) return 'the buffers the chain reads';
    if (n.culled) return `culled: ${n.reason}`;
    const time = plan.times?.[n.id];
    return [n.device, time?.ms !== undefined ? `${time.ms.toFixed(1)} ms` : '', time?.reused ? 'reused' : ''].filter(Boolean).join(' · ');
  };
  // Box width: the longest line of any node (10 px text, about 6.2 px a letter).
  const charW = 6.2, rowH = 12, pad = 8;
  const letters = (n) => Math.max(n.label.length, subtitle(n).length, ...n.outputs.map((o) => o.length + 4));
  const nodeW = Math.ceil(Math.max(110, ...nodes.map((n) => letters(n) * charW + 10)));
  const panel = $('graph').clientWidth || 320;
  const perRow = page.graphFit ? Math.max(1, Math.floor((panel - pad) / (nodeW + pad))) : Infinity;
  const pos = new Map();
  let y = pad, widest = 1;
  for (let rank = 0; rank <= lastRank; ++rank) {
    const meanX = (n) => {
      const xs = n.sources.map((id) => pos.get(id)?.x).filter((x) => x !== undefined);
      return xs.length ? xs.reduce((a, b) => a + b, 0) / xs.length : 0;
    };
    const members = nodes.filter((n) => n.rank === rank).sort((a, b) => meanX(a) - meanX(b));
    for (let i = 0; i < members.length; i += perRow) {
      const row = members.slice(i, i + perRow);
      let h = 0;
      row.forEach((n, k) => {
        const nh = 30 + rowH * n.outputs.length;
        pos.set(n.id, { x: pad + k * (nodeW + pad), y, h: nh });
        h = Math.max(h, nh);
      });
      widest = Math.max(widest, row.length);
      y += h + 3 * pad;  // room for the edges into the next row
    }
  }
  const width = pad + widest * (nodeW + pad);
  const svg = document.createElementNS(SVG_NS, 'svg');
  svg.setAttribute('viewBox', `0 0 ${width} ${y}`);
  // Wider than the panel only when one box is: then scaled to fit, or at its natural size.
  svg.setAttribute('width', page.graphFit ? Math.min(width, panel) : width);
  svg.setAttribute('height', page.graphFit ? y * Math.min(1, panel / width) : y);
  for (const n of nodes) {
    const to = pos.get(n.id);
    for (const id of n.sources) {
      const from = pos.get(id);
      if (!from) continue;
      const x0 = from.x + nodeW / 2, y0 = from.y + from.h, x1 = to.x + nodeW / 2, y1 = to.y;
      const bend = Math.max(12, (y1 - y0) / 2);
      el('path', { d: `M${x0},${y0} C${x0},${y0 + bend} ${x1},${y1 - bend} ${x1},${y1}` }, svg);
    }
  }
  for (const n of nodes) {
    const p = pos.get(n.id);
    const time = plan.times?.[n.id];
    const g = el('g', { class: `node${n.capture ? ' capture' : ''}${n.device === 'cuda' ? ' gpu' : ''}${n.culled ? ' culled' : ''}${time?.reused ? ' reused' : ''}`, 'data-pass': n.id }, svg);
    el('rect', { x: p.x, y: p.y, width: nodeW, height: p.h }, g);
    el('text', { x: p.x + 5, y: p.y + 12, 'font-weight': 'bold' }, g).textContent = n.label;
    el('text', { x: p.x + 5, y: p.y + 24, class: 'time' }, g).textContent = subtitle(n);
    if (n.culled) el('title', {}, g).textContent = n.reason;
    n.outputs.forEach((o, i) => {
      const name = n.capture ? o : `${n.id}.${o}`;
      const kind = plan.kinds?.[name] || 'data';
      const port = el('text', { x: p.x + 10, y: p.y + 36 + i * rowH, class: `port ${kind}`, 'data-buffer': name }, g);
      port.textContent = `${kind === 'data' ? '▹' : '▸'} ${o}`;
      el('title', {}, port).textContent = `${name}: ${{ colour: 'colour (drawn through the view)', display: 'display-referred (drawn as it is)', data: 'data (drawn as it is)' }[kind]}; click: A, shift-click: B`;
      port.addEventListener('click', (ev) => selectBuffer(ev.shiftKey ? 'b' : 'a', name));
    });
  }
  $('graph').replaceChildren(svg);
  markShownPorts();
}

// A and B named on the image, with how each is drawn; the one on screen stands out.
function showLabels() {
  const v = page.viewer, mode = $('mode').value;
  const view = $('view').selectedOptions[0]?.text || '';
  const how = (img) => (!img ? '' : img.color ? ` · colour, via ${view}` : ' · as it is');
  $('label-a').textContent = `A  ${page.shown.a || ''}${how(v?.a)}`;
  const b = page.snapshotB ? `snapshot: ${page.snapshotB.label}` : page.shown.b;
  $('label-b').textContent = b ? `B  ${b}${how(v?.b)}` : '';
  $('label-a').title = $('label-b').title = 'colour is drawn through the view; data and display-referred images as they are';
  $('label-b').hidden = !b;
  $('label-a').classList.toggle('active', mode !== 'b');
  $('label-b').classList.toggle('active', !!b && mode !== 'a');
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
    // A reused pass shows the time of the run that made its outputs, marked.
    const last = p.reused ? report.lastExecuted?.[p.name] : null;
    tr.className = p.reused ? 'reused' : '';
    tr.insertCell().textContent = p.name;
    const ms = tr.insertCell();
    ms.className = 'num';
    ms.textContent = p.reused ? (last ? last.ms.toFixed(2) : '–') : (p.seconds * 1e3).toFixed(2);
    const note = tr.insertCell();
    note.textContent = p.reused ? 'reused' : '';
    if (last) note.title = `outputs of change ${last.generation}, which ran it in ${last.ms.toFixed(2)} ms`;
  }
  $('timing').textContent = `frame ${report.frame}: ${report.wallMs.toFixed(1)} ms wall, ` +
    `${report.executedSteps} run, ${report.reusedSteps} reused`;
  // The error figures: one row per error measure.
  const table = $('errors');
  table.textContent = '';
  // FLIP beside them where an error measure takes it (error_measure's flip parameter).
  const figures = ['rmse', 'relMse', 'bias'];
  if (Object.values(report.errors || {}).some((f) => f.flip !== undefined)) figures.push('flip');
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

// Methods at a glance: each error measure's RMSE against the time of the passes its source
// depends on (the server pairs them), this run's points bright, earlier settings' dimmed.
function buildMethods(report, params) {
  if (!report?.methods) return;
  const runs = page.methodRuns;
  if (!runs.length || runs[0].generation !== report.generation)
    runs.unshift({ generation: report.generation, label: settingsLabel(params.settings), methods: report.methods.filter((m) => m.rmse !== undefined) });
  runs.length = Math.min(runs.length, 12);
  const all = runs.flatMap((r) => r.methods);
  const el = svgElement;
  const W = 320, H = 170, left = 40, bottom = 22, top = 8, right = 8;
  // Time linear from 0; RMSE on a log scale (measures of one chain differ by decades).
  const xMax = Math.max(1e-3, ...all.map((m) => m.ms)) * 1.1;
  const positive = all.map((m) => m.rmse).filter((e) => e > 0);
  const yMax = Math.max(1e-9, ...positive) * 1.25, yMin = Math.min(yMax / 10, ...positive.map((e) => e * 0.8));
  const x = (ms) => left + (ms / xMax) * (W - left - right);
  const y = (e) => H - bottom - (Math.log(Math.max(e, yMin) / yMin) / Math.log(yMax / yMin)) * (H - bottom - top);
  const svg = document.createElementNS(SVG_NS, 'svg');
  svg.setAttribute('viewBox', `0 0 ${W} ${H}`);
  el('path', { class: 'axis', d: `M${left},${top} V${H - bottom} H${W - right}` }, svg);
  el('text', { x: left, y: H - 6 }, svg).textContent = '0';
  el('text', { x: W - right, y: H - 6, 'text-anchor': 'end' }, svg).textContent = `${xMax.toPrecision(2)} ms of its passes`;
  el('text', { x: left - 3, y: top + 8, 'text-anchor': 'end' }, svg).textContent = yMax.toPrecision(2);
  el('text', { x: left - 3, y: H - bottom, 'text-anchor': 'end' }, svg).textContent = yMin.toPrecision(2);
  el('text', { x: left + 4, y: top + 8 }, svg).textContent = 'RMSE (log)';
  const colours = ['#5fa8ff', '#f0a35e', '#7fd17f', '#e07ad0', '#e0d060', '#60d0d0'];
  const names = [...new Set(all.map((m) => m.measure))];
  runs.forEach((run, i) => {
    const g = el('g', { class: i === 0 ? 'now' : 'earlier' }, svg);
    for (const m of run.methods) {
      const c = el('circle', { cx: x(m.ms), cy: y(m.rmse), r: i === 0 ? 4 : 3, fill: colours[names.indexOf(m.measure) % colours.length],
                               'data-measure': m.measure, 'data-generation': run.generation }, g);
      el('title', {}, c).textContent = `${m.measure}: RMSE ${m.rmse.toPrecision(3)} at ${m.ms.toFixed(2)} ms (${m.passes.join(', ')}); change ${run.generation}: ${run.label}`;
      if (i === 0) el('text', { x: x(m.ms) + 6, y: y(m.rmse) + 3 }, g).textContent = m.measure;
    }
  });
  $('methods').replaceChildren(svg);
}

// The error taken apart, as bench does it: converged, screen-space limit, one bounce, full.
async function breakdown() {
  const out = $('breakdown-text');
  out.textContent = 'taking the error apart…';
  try {
    const r = await getJSON(`/api/breakdown?rays=${+$('breakdown-rays').value}`);
    // Each measure's error as bars: every step's share of the squared error (a step that pulls
    // toward the truth, a negative share, in grey), its RMSE in the tooltip, then the sentence.
    out.textContent = '';
    const taken = r.errors.filter((e) => e.decomposition);
    for (const e of taken) {
      const d = e.decomposition;
      out.append(Object.assign(document.createElement('h3'), { textContent: `${e.name}: RMSE ${d.rmse.toPrecision(3)}` }));
      for (const s of d.steps) {
        const row = Object.assign(document.createElement('div'), { className: 'share', title: `${s.from} → ${s.to}: RMSE ${s.rmse.toPrecision(4)}, bias ${s.bias.toPrecision(3)}` });
        const track = Object.assign(document.createElement('div'), { className: 'track' });
        const bar = Object.assign(document.createElement('div'), { className: `bar${s.share < 0 ? ' cancels' : ''}` });
        bar.style.width = `${Math.min(100, Math.abs(s.share) * 100)}%`;
        track.append(bar);
        row.append(Object.assign(document.createElement('span'), { textContent: s.name }), track,
                   Object.assign(document.createElement('span'), { className: 'value', textContent: `${(100 * s.share).toFixed(0)} %` }));
        out.append(row);
      }
      out.append(Object.assign(document.createElement('div'), { className: 'breakdown-sentence', textContent: d.sentence }));
    }
    if (!taken.length) out.textContent = 'no error measure here compares a screen-space pass with a truth layer';
    out.append(Object.assign(document.createElement('div'), { textContent: `(${r.rays} rays, ${(r.ms / 1000).toFixed(1)} s)` }));
  } catch (e) {
    out.textContent = e.message;
  }
}

// The settings ({cvars: {name: value}, set: {name: value}, inputs: {name: source}}) as
// NAME=VALUE words.
function settingsLabel(settings) {
  const all = [...Object.entries(settings.cvars), ...Object.entries(settings.set), ...Object.entries(settings.inputs || {})]
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
  if (which === 'b') showSnapshotAsB(null);
  page.shown[which] = name;
  $(`buffer-${which}`).value = name;
  markShownPorts();
  showLabels();
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
    if (which === 'a') page.viewer.setA(image);
    else if (!page.snapshotB) page.viewer.setB(image);
    showLabels();
    statistics();
    page.viewer.gl.finish();
    if (which === 'a' && page.pending && image.generation >= page.pending.generation) {
      page.timings.push({ ...page.pending, fetchStart: start, fetched, drawn: performance.now(), bytes: image.data.byteLength });
      page.pending = null;
    }
  } catch (e) {
    setStatus(`${name}: ${e.message}`, true);
  }
}

// ---------------------------------------------------------------------------------------------
// Snapshots: any buffer of any earlier setting, kept on the page to compare against as B.

function pinA() {
  const v = page.viewer;
  if (!v.a) return;
  const label = `${v.a.name} · change ${v.a.generation} · ${settingsLabel(page.params.settings)}`;
  page.snapshots.unshift({ label, image: { ...v.a, name: `snapshot ${page.snapshots.length + 1}` } });
  page.snapshots.length = Math.min(page.snapshots.length, 12);
  listSnapshots();
}

function showSnapshotAsB(snapshot) {
  const had = page.snapshotB;
  page.snapshotB = snapshot;
  if (had && !snapshot) page.viewer.setB(null);
  if (snapshot) {
    page.shown.b = null;
    $('buffer-b').value = '';
    page.viewer.setB(snapshot.image);
    markShownPorts();
  }
  listSnapshots();
  showLabels();
  statistics();
}

function listSnapshots() {
  const list = $('snapshots');
  list.textContent = '';
  for (const s of page.snapshots) {
    const li = document.createElement('li');
    li.textContent = s.label;
    li.classList.toggle('as-b', s === page.snapshotB);
    const asB = Object.assign(document.createElement('button'), { type: 'button', textContent: 'as B' });
    asB.addEventListener('click', () => showSnapshotAsB(s));
    const drop = Object.assign(document.createElement('button'), { type: 'button', textContent: '×', title: 'forget it' });
    drop.addEventListener('click', () => {
      page.snapshots = page.snapshots.filter((x) => x !== s);
      if (page.snapshotB === s) showSnapshotAsB(null); else listSnapshots();
    });
    li.append(asB, drop);
    list.append(li);
  }
}

// ---------------------------------------------------------------------------------------------
// Statistics over a rectangle (shift-drag): A's mean per channel, and the RMSE of A against B.

function statistics() {
  const v = page.viewer, r = page.rect, a = v.a;
  if (!r || !a) { page.rectStats = null; $('rect-stats').textContent = ''; return; }
  const [x0, y0, x1, y1] = r;
  const n = a.channels.length, count = (x1 - x0) * (y1 - y0);
  const mean = new Array(n).fill(0);
  const b = v.b && v.b.width === a.width && v.b.height === a.height && v.b.channels.length === n ? v.b : null;
  let squared = 0;
  for (let y = y0; y < y1; ++y)
    for (let x = x0; x < x1; ++x) {
      const i = (y * a.width + x) * n;
      for (let c = 0; c < n; ++c) {
        mean[c] += a.data[i + c];
        if (b) squared += (a.data[i + c] - b.data[i + c]) ** 2;
      }
    }
  for (let c = 0; c < n; ++c) mean[c] /= count;
  const rmse = b ? Math.sqrt(squared / (count * n)) : null;
  page.rectStats = { rect: r, pixels: count, mean, rmse };
  const means = a.channels.map((c, k) => `${c}=${mean[k].toPrecision(6)}`).join(' ');
  $('rect-stats').textContent = `rectangle ${x0},${y0}–${x1 - 1},${y1 - 1} (${count} pixels): A mean ${means}` +
    (b ? `; RMSE of A against B ${rmse.toPrecision(6)}` : b === null && v.b ? '; B differs in size or channels: no RMSE' : '');
}

// The rectangle's outline, kept on its pixels as the image is zoomed and panned.
function placeRect() {
  const r = page.rect, box = $('rect'), s = page.viewer.state;
  box.hidden = !r;
  if (!r) return;
  Object.assign(box.style, { left: `${s.pan[0] + r[0] * s.zoom}px`, top: `${s.pan[1] + r[1] * s.zoom}px`,
    width: `${(r[2] - r[0]) * s.zoom}px`, height: `${(r[3] - r[1]) * s.zoom}px` });
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

// The picture first, the panels after it: on a machine of few cores the server, the page's
// layout and the browser's drawing share them, and the image is what the user waits for.
async function refresh() {
  await Promise.all(['a', 'b'].map((w) => (isPassOutput(page.shown[w]) || !page.viewer[w] ? loadShown(w) : null)));
  const [params, plan, report] = await Promise.all([getJSON('/api/params'), getJSON('/api/graph'), getJSON('/api/report')]);
  page.params = params;
  markShadowed(params);
  buildGraph(plan);
  buildReport(report);
  $('frame-label').textContent = `frame ${params.frame}`;
  if (report) pushHistory(report, params);
  buildMethods(report, params);
  return report;
}

// The connection as the page shows it: open, lost (the server stopped or the network went), and
// back. EventSource reconnects by itself; once back, the page reads the settings and the last run
// again, so the controls show what the server runs (a restarted server starts as loaded).
function setConnection(state, text = '') {
  document.body.dataset.connection = state;
  $('connection').textContent = text;
  $('connection').className = `connection ${state}`;
}

async function resync() {
  const params = await getJSON('/api/params');
  page.params = params;
  buildControls(params);
  const report = await refresh();
  const s = await getJSON('/api/status');
  // A restarted server counts its changes from 1 again.
  page.generation = s.requested;
  page.pending = null;
  if (report) document.body.dataset.generation = report.generation;
  return s;
}

// A run shorter than this shows no per-pass progress.
const kQuietRunMs = 250;

function listen() {
  const events = new EventSource('/api/events');
  let run = { generation: -1, started: 0 };  // the run the pass events are of, and its first event's time
  events.onerror = () => {
    if (document.body.dataset.connection !== 'lost')
      setConnection('lost', 'lost the server: it stopped or cannot be reached; reconnecting…');
  };
  events.onopen = async () => {
    if (document.body.dataset.connection !== 'lost') return setConnection('open');
    try {
      const s = await resync();
      setConnection('open', "reconnected: the controls show the server's settings");
      if (s.status === 'error') setStatus(`the server's last run failed: ${s.message}`, true);
      else setStatus('ready');
    } catch (e) {
      setConnection('lost', `reconnected, but: ${e.message}`);
    }
  };
  events.onmessage = async (msg) => {
    const e = JSON.parse(msg.data);
    if (e.type === 'pass') {
      // Progress only for a run that lasts (any run: a slider's, the first frame's, another
      // client's): each update is a redraw of the page, which on a software-rendered browser
      // takes the cores the run needs.
      if (e.generation !== run.generation) run = { generation: e.generation, started: performance.now() };
      if (performance.now() - run.started < kQuietRunMs) return;
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
  // Beside the OCIO views: Unreal 4.27's filmic tonemapper (its defaults), as a viewport shows.
  const FILM = 'ue4.27-film';
  $('view').append(new Option('UE 4.27 film', FILM));
  $('view').value = display?.defaultView || '';
  const loadLut = async () => {
    try {
      if ($('view').value === FILM) {
        const res = await api('/api/film-cube');
        viewer.setFilmCube(new Float32Array(await res.arrayBuffer()), +res.headers.get('X-Size'),
          +res.headers.get('X-Log2-Min'), +res.headers.get('X-Log2-Max'));
        viewer.state.film = 1;
      } else {
        const table = new Float32Array(await (await api(`/api/lut?view=${encodeURIComponent($('view').value)}`)).arrayBuffer());
        viewer.setLut(table);
        viewer.state.film = 0;
      }
      viewer.lutReady = true;
      showLabels();
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
  $('mode').addEventListener('change', () => { state.mode = modes[$('mode').value]; showLabels(); viewer.draw(); });
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
    if (page.snapshotB) return setStatus('a snapshot is compared as B only: show a buffer as B to flip');
    [page.shown.a, page.shown.b] = [page.shown.b || page.shown.a, page.shown.a];
    [viewer.a, viewer.b] = [viewer.b || viewer.a, viewer.a];
    $('buffer-a').value = page.shown.a;
    $('buffer-b').value = page.shown.b || '';
    if (viewer.a) viewer.upload(0, 'imgA', viewer.a);
    if (viewer.b) viewer.upload(1, 'imgB', viewer.b);
    markShownPorts();
    showLabels();
    viewer.draw();
  };
  $('flip').addEventListener('click', flip);
  $('fit').addEventListener('click', () => viewer.fit());
  // tev's keys (docs/serve.md), wherever the focus is except in a field that takes text.
  const setSelect = (id, value) => { $(id).value = value; $(id).dispatchEvent(new Event('change')); };
  const exposeBy = (stops) => {
    const e = $('exposure');
    e.value = Math.max(+e.min, Math.min(+e.max, +e.value + stops));
    e.dispatchEvent(new Event('input'));
  };
  const channelKey = (isolate) => setSelect('channel', String(state.isolate === isolate ? 0 : isolate));
  const keys = {
    e: () => exposeBy(0.5), E: () => exposeBy(-0.5),
    r: () => channelKey(1), g: () => channelKey(2), b: () => channelKey(3), a: () => channelKey(4),
    l: () => channelKey(5),
    f: () => viewer.fit(), '+': () => viewer.zoomBy(1.25), '=': () => viewer.zoomBy(1.25),
    '-': () => viewer.zoomBy(0.8), 0: () => viewer.zoomBy(1, undefined, undefined, 1),
    1: () => setSelect('mode', 'a'), 2: () => setSelect('mode', 'b'), d: () => setSelect('mode', 'diff'),
    w: () => setSelect('mode', 'wipe'), x: flip, p: pinA,
  };
  const takesText = (el) => el.isContentEditable || el.tagName === 'TEXTAREA' ||
    (el.tagName === 'INPUT' && !['range', 'checkbox', 'radio', 'button'].includes(el.type));
  document.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey || takesText(e.target)) return;
    const action = keys[e.key];
    if (!action) return;
    e.preventDefault();  // a focused select's type-ahead would change it too
    action();
  });
  const canvas = $('canvas');
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const rect = canvas.getBoundingClientRect();
    const cx = e.clientX - rect.left, cy = e.clientY - rect.top;
    viewer.zoomBy(e.deltaY < 0 ? 1.25 : 0.8, cx, cy);
  }, { passive: false });
  let drag = null;
  // Drag pans; shift-drag draws the statistics rectangle (a click without a drag clears it).
  let corner = null;
  const pixelUnder = (e, round) => {
    const rect = canvas.getBoundingClientRect();
    const [x, y] = viewer.imagePoint(e.clientX - rect.left, e.clientY - rect.top);
    const clampTo = (v, hi) => Math.max(0, Math.min(hi, round(v)));
    return [clampTo(x, viewer.a.width), clampTo(y, viewer.a.height)];
  };
  canvas.addEventListener('mousedown', (e) => {
    if (e.shiftKey && viewer.a) corner = pixelUnder(e, Math.floor);
    else drag = [e.clientX, e.clientY];
  });
  window.addEventListener('mouseup', (e) => {
    if (corner) {
      const end = pixelUnder(e, Math.ceil);
      const r = [Math.min(corner[0], end[0]), Math.min(corner[1], end[1]), Math.max(corner[0] + 1, end[0]), Math.max(corner[1] + 1, end[1])];
      page.rect = r[2] - r[0] > 1 || r[3] - r[1] > 1 ? r : null;
      corner = null;
      placeRect();
      statistics();
    }
    drag = null;
  });
  viewer.onDraw = placeRect;
  $('pin').addEventListener('click', pinA);
  canvas.addEventListener('mousemove', (e) => {
    if (drag) {
      state.pan = [state.pan[0] + e.clientX - drag[0], state.pan[1] + e.clientY - drag[1]];
      drag = [e.clientX, e.clientY];
      viewer.fitted = false;
      viewer.draw();
    }
    probe(e);
  });

  $('graph-fit').addEventListener('click', () => {
    page.graphFit = !page.graphFit;
    $('graph-fit').textContent = page.graphFit ? 'one row per layer' : 'fit the panel';
    buildGraph(page.plan);
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
  if (report) {
    setStatus('ready');
    document.body.dataset.generation = report.generation;
  } else {
    // No run has finished: the first is running, or it failed (a missing capture, say).
    const s = await getJSON('/api/status');
    if (s.status === 'error') setStatus(`the first frame failed: ${s.message}`, true);
    else setStatus('running the first frame…');
  }
}

main().catch((e) => setStatus(e.message, true));
