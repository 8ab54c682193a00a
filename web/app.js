// The page: a scene and one or two algorithms, rendered by hsr's WebAssembly module (hsr.js),
// with the mouse orbiting the camera, the four buffers side by side, the statistics, two
// algorithms' disagreement, and an algorithm's steps as `hsr explain` shows them.
//
// index.html?scene=spheres:3000&algorithms=warnock,painter-naive&size=320x240&step=5 opens the page
// so; with test=1 (or test=all: every algorithm) it also writes each algorithm's canvas bytes
// (read back from the canvas) into #test-result, for the browser test (web/test/browser_test.mjs).

import {Hsr} from './hsr.js';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const hsr = new Hsr(await createHsr());  // createHsr: hsr_web.js, loaded before this module
const catalogue = hsr.catalogue();

const state = {
  camera: null,  // {eye, target, up, fov_deg}: the orbit's, null until the first render
  orbit: null,   // {radius, azimuth, elevation} about camera.target
  frames: {},    // the last frames of A and B
};

// ---------------------------------------------------------------------------------------------
// Controls

function fillSelect(select, items, selected) {
  select.replaceChildren(...items.map(({value, label}) => {
    const o = document.createElement('option');
    o.value = value;
    o.textContent = label;
    o.selected = value === selected;
    return o;
  }));
}

// A scene named in the address: its catalogue entry ("spheres:3000" is "spheres:N")
const named = (params.get('scene') || 'demo').split(':')[0];
fillSelect($('scene'), catalogue.scenes.map((s) => ({value: s.name, label: `${s.name}: ${s.summary}`})),
           catalogue.scenes.find((s) => s.name.split(':')[0] === named)?.name || 'demo');
const algorithmItems = catalogue.algorithms.map((a) => ({value: a.name, label: a.name}));
const [firstAlgorithm, secondAlgorithm] = (params.get('algorithms') || 'zbuffer,warnock').split(',');
fillSelect($('algorithm-a'), algorithmItems, firstAlgorithm);
fillSelect($('algorithm-b'), [{value: '', label: '(none)'}, ...algorithmItems], secondAlgorithm || '');
if (params.get('size')) $('size').value = params.get('size');

// The built-in spec the controls name: "spheres:N" takes the count box
function sceneSpec() {
  const name = $('scene').value;
  const count = Math.max(1, Math.min(200000, Number($('count').value) || 1));
  if (name.startsWith('spheres')) return `spheres:${count}`;
  if (name.startsWith('soup')) return `soup:${count}:1`;
  return name;
}

function size() {
  const [w, h] = $('size').value.split('x').map(Number);
  return {width: w, height: h};
}

// The request every render and explanation sends: algorithm, size, camera, GL-style controls
function request(algorithm) {
  return {
    algorithm, ...size(),
    // None while the camera is the framing one: exactly `hsr render`'s
    camera: state.original ? undefined : state.camera,
    cull: $('cull').value,
    front_face: $('front-face').value,
    depth_test: $('depth-test').checked,
    depth_func: $('depth-func').value,
    depth_mask: $('depth-mask').checked,
    clear_depth: Number($('clear-depth').value),
    polygon_mode: $('polygon-mode').value,
    outline: $('outline').checked,
  };
}

function status(text, error = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', error);
}

// ---------------------------------------------------------------------------------------------
// Scene and camera

function showScene(info) {
  $('scene-info').textContent =
      `${info.name}: ${info.polygons.toLocaleString()} polygons, ${info.triangles.toLocaleString()} triangles, ` +
      `${info.objects} object${info.objects === 1 ? '' : 's'}`;
  resetCamera();
}

// The camera hsr frames the scene with, as the start of the orbit
function resetCamera() {
  const c = hsr.scene(size()).camera;
  const d = c.eye.map((e, i) => e - c.target[i]);
  const radius = Math.hypot(...d);
  state.orbit = {radius, azimuth: Math.atan2(d[0], d[2]), elevation: Math.asin(d[1] / radius)};
  state.camera = {eye: c.eye, target: c.target, up: c.up, fov_deg: c.fov_deg};
  state.original = true;  // the framing camera itself: the page sends none, as `hsr render`
}

function orbitCamera() {
  const {radius, azimuth, elevation} = state.orbit, t = state.camera.target;
  state.camera = {
    ...state.camera,
    eye: [t[0] + radius * Math.cos(elevation) * Math.sin(azimuth), t[1] + radius * Math.sin(elevation),
          t[2] + radius * Math.cos(elevation) * Math.cos(azimuth)],
    up: [0, 1, 0],
  };
  state.original = false;
}

function loadBuiltin() {
  try {
    showScene(hsr.load(sceneSpec()));
    $('count-label').style.display = /spheres|soup/.test($('scene').value) ? '' : 'none';
    renderAll();
  } catch (e) {
    status(e.message, true);
  }
}

async function loadFile(file) {
  try {
    showScene(hsr.loadObj(await file.text(), file.name));
    renderAll();
  } catch (e) {
    status(e.message, true);
  }
}

// ---------------------------------------------------------------------------------------------
// Pictures

function draw(canvas, width, height, rgba) {
  canvas.width = width;
  canvas.height = height;
  canvas.getContext('2d').putImageData(new ImageData(rgba, width, height), 0, 0);
}

// A render's time as the page measured it ("" where the clock did not move: a headless
// browser's virtual time, as in the screenshots)
const took = (frame) => (frame.ms > 0 ? `: ${frame.ms.toFixed(1)} ms` : '');

function renderOne(algorithm) {
  const t0 = performance.now();
  const frame = hsr.render(request(algorithm));
  frame.ms = performance.now() - t0;
  return frame;
}

function renderAll() {
  const a = $('algorithm-a').value, b = $('algorithm-b').value;
  const info = catalogue.algorithms.find((x) => x.name === a);
  $('algorithm-info').textContent = `${info.summary} (${info.source}). Capabilities: ${info.capabilities || 'none'}.`;
  try {
    const fa = renderOne(a);
    state.frames.a = fa;
    draw($('color-a'), fa.width, fa.height, fa.picture('color'));
    for (const kind of ['depth', 'ids', 'overdraw']) draw($(`${kind}-a`), fa.width, fa.height, fa.picture(kind));
    $('caption-a').textContent = `A: ${a}${took(fa)}`;
    showStats(fa.stats);
    let text = `${a}${took(fa)}`;
    $('figure-b').hidden = $('figure-diff').hidden = !b;
    if (b) {
      const fb = renderOne(b);
      state.frames.b = fb;
      draw($('color-b'), fb.width, fb.height, fb.picture('color'));
      $('caption-b').textContent = `B: ${b}${took(fb)}`;
      const differ = drawDisagreement(fa, fb);
      const drawn = fa.ids.reduce((n, id) => n + (id !== 0xffffffff ? 1 : 0), 0);
      $('caption-diff').textContent = `A and B show different polygons at ${differ} of ${drawn} drawn pixels` +
          (drawn ? ` (${(100 * differ / drawn).toFixed(3)}%)` : '');
      text += ` · ${b}${took(fb)} · ${differ} pixels differ`;
    }
    status(text);
  } catch (e) {
    status(e.message, true);
  }
}

// A's picture dimmed, with the pixels where B shows another polygon in magenta
function drawDisagreement(fa, fb) {
  const color = fa.picture('color'), out = new Uint8ClampedArray(color.length);
  let differ = 0;
  for (let i = 0; i < fa.ids.length; ++i) {
    const k = 4 * i;
    if (fa.ids[i] !== fb.ids[i]) {
      ++differ;
      out[k] = 230, out[k + 1] = 0, out[k + 2] = 200;
    } else {
      out[k] = 128 + color[k] / 2, out[k + 1] = 128 + color[k + 1] / 2, out[k + 2] = 128 + color[k + 2] / 2;
    }
    out[k + 3] = 255;
  }
  draw($('diff'), fa.width, fa.height, out);
  return differ;
}

function showStats(stats) {
  const rows = [];
  const add = (name, value) => rows.push(`<tr><th>${name}</th><td>${value}</td></tr>`);
  for (const [name, value] of Object.entries(stats.fields)) if (value) add(name.replaceAll('_', ' '), value.toLocaleString());
  for (const [name, value] of Object.entries(stats.counters)) add(name, value.toLocaleString());
  if (stats.total_ms > 0) {
    for (const s of stats.stages) add(`time: ${s.name}`, `${s.ms.toFixed(2)} ms`);
    add('total', `${stats.total_ms.toFixed(2)} ms`);
  }
  $('stats').innerHTML = rows.join('');
}

// ---------------------------------------------------------------------------------------------
// Explain: the algorithm's steps, the caption in the notes' words, what each step works on
// outlined in red

let explanation = null;

function runExplain() {
  const a = $('algorithm-a').value;
  const info = catalogue.algorithms.find((x) => x.name === a);
  $('explain-title').textContent = a;
  if (!info.explain) {
    explanation = null;
    $('step').disabled = true;
    $('step-caption').textContent = `${a} cannot explain its steps yet: choose ` +
        catalogue.algorithms.filter((x) => x.explain).map((x) => x.name).join(', ') + '.';
    return;
  }
  try {
    explanation = hsr.explain(request(a));
    $('step').max = explanation.steps.length;
    $('step').value = 1;
    $('step').disabled = false;
    showStep();
  } catch (e) {
    status(e.message, true);
  }
}

function showStep() {
  if (!explanation) return;
  const i = Number($('step').value) - 1, s = explanation.steps[i];
  $('step-number').textContent = `step ${s.number} of ${explanation.steps.length}: ${s.name}`;
  $('step-caption').textContent = s.caption;
  for (const kind of ['color', 'depth']) {
    const canvas = $(`step-${kind}`);
    draw(canvas, explanation.width, explanation.height, s[kind]);
    const g = canvas.getContext('2d');
    g.strokeStyle = '#e0201a';
    g.lineWidth = 1;
    for (const o of s.outlines) {
      g.beginPath();
      for (let k = 0; k < o.length; k += 2) g[k ? 'lineTo' : 'moveTo'](o[k] + 0.5, o[k + 1] + 0.5);
      g.closePath();
      g.stroke();
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Events

let pending = false;
function rerender() {
  if (pending) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    renderAll();
  });
}

for (const canvas of [$('color-a'), $('color-b')]) {
  let last = null;
  canvas.addEventListener('pointerdown', (e) => {
    last = [e.clientX, e.clientY];
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointerup', () => (last = null));
  canvas.addEventListener('pointermove', (e) => {
    if (!last) return;
    state.orbit.azimuth -= (e.clientX - last[0]) * 0.01;
    state.orbit.elevation = Math.max(-1.5, Math.min(1.5, state.orbit.elevation + (e.clientY - last[1]) * 0.01));
    last = [e.clientX, e.clientY];
    orbitCamera();
    rerender();
  });
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    state.orbit.radius *= Math.exp(e.deltaY * 0.001);
    orbitCamera();
    rerender();
  }, {passive: false});
}

$('scene').addEventListener('change', loadBuiltin);
$('count').addEventListener('change', loadBuiltin);
$('file').addEventListener('change', (e) => e.target.files[0] && loadFile(e.target.files[0]));
$('drop').addEventListener('dragover', (e) => e.preventDefault());
$('drop').addEventListener('drop', (e) => {
  e.preventDefault();
  if (e.dataTransfer.files[0]) loadFile(e.dataTransfer.files[0]);
});
for (const id of ['algorithm-a', 'algorithm-b', 'cull', 'front-face', 'depth-test', 'depth-func', 'depth-mask',
                  'clear-depth', 'polygon-mode', 'outline'])
  $(id).addEventListener('change', renderAll);
$('size').addEventListener('change', () => {
  const original = state.original;
  if (original) resetCamera();
  renderAll();
});
$('reset-camera').addEventListener('click', () => {
  resetCamera();
  renderAll();
});
$('explain-run').addEventListener('click', runExplain);
$('step').addEventListener('input', showStep);

// ---------------------------------------------------------------------------------------------
// Start, and the browser test's read-back

$('count').value = (params.get('scene') || '').split(':')[1] || 2000;
loadBuiltin();
runExplain();
if (params.get('step') && explanation) {
  $('step').value = params.get('step');
  showStep();
}
if (params.get('test')) {
  // Each algorithm named (test=all: every algorithm of the registry) drawn as A in turn, its
  // colour read back from the canvas as base64, for the test to compare with the native PNG
  const names = params.get('test') === 'all' ? catalogue.algorithms.map((x) => x.name) : [firstAlgorithm, secondAlgorithm];
  const result = {};
  for (const name of names.filter(Boolean)) {
    $('algorithm-a').value = name;
    renderAll();
    const c = $('color-a');
    const bytes = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let binary = '';
    for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    result[name] = {width: c.width, height: c.height, rgba: btoa(binary), status: $('status').textContent};
  }
  $('algorithm-a').value = firstAlgorithm;
  renderAll();
  $('test-result').textContent = JSON.stringify(result);
  document.body.dataset.ready = 'yes';
}
