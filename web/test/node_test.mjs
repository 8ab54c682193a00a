// The web module against the native build, byte for byte: for each built-in scene and every
// algorithm of the registry, the module's colour, depth, ids and overdraw against what the
// native `hsr render` writes (its PNG and --raw .npy files) for the same scene, algorithm,
// size and controls; the orbit camera against --eye/--target/--up; every explainable
// algorithm's steps (names and captions) against `hsr explain`'s steps.md; OBJ text against the
// same file read natively by assimp. Any difference fails the run.
//
//   node web/test/node_test.mjs BUILD_WASM_WEB_DIR NATIVE_HSR [WORK_DIR]

import {execFileSync} from 'node:child_process';
import fs from 'node:fs';
import {createRequire} from 'node:module';
import os from 'node:os';
import path from 'node:path';

import {Hsr, HsrError} from '../hsr.js';
import {firstDifference, readNpyData, readPng} from './native_files.mjs';

const [moduleDir, nativeHsr, workArg] = process.argv.slice(2);
if (!moduleDir || !nativeHsr) {
  console.error('usage: node_test.mjs BUILD_WASM_WEB_DIR NATIVE_HSR [WORK_DIR]');
  process.exit(2);
}
const work = workArg || fs.mkdtempSync(path.join(os.tmpdir(), 'hsr-web-'));
fs.mkdirSync(work, {recursive: true});

const createHsr = createRequire(import.meta.url)(path.resolve(moduleDir, 'hsr_web.js'));
const hsr = new Hsr(await createHsr({wasmBinary: fs.readFileSync(path.join(moduleDir, 'hsr_web.wasm'))}));

const WIDTH = 96, HEIGHT = 72;
const SCENES = ['demo', 'solids', 'cyclic', 'penetrating', 'spheres:300', 'soup:200:7'];
// Controls beside the defaults, each on the demo scene with every algorithm that takes them
const CONTROLS = [
  {request: {cull: 'back'}, flags: ['--cull', 'back']},
  {request: {cull: 'front', front_face: 'cw'}, flags: ['--cull', 'front', '--front-face', 'cw']},
  {request: {depth_func: 'greater', clear_depth: 0}, flags: ['--depth-func', 'greater', '--clear-depth', '0'],
   capability: 'depth-funcs'},
  {request: {polygon_mode: 'line'}, flags: ['--polygon-mode', 'line'], capability: 'polygon-modes'},
  {request: {outline: true}, flags: ['--outline'], capability: 'outline'},
  {request: {depth_test: false}, flags: ['--no-depth-test'], capability: 'depth-funcs'},
];

let compared = 0, bytes = 0;
const failures = [];

function native(args) {
  try {
    execFileSync(nativeHsr, args, {stdio: ['ignore', 'pipe', 'pipe']});
    return null;
  } catch (e) {
    return (e.stderr || '').toString().trim() || `exit ${e.status}`;
  }
}

function same(label, ours, theirs) {
  const at = firstDifference(ours, theirs);
  bytes += ours.length;
  if (at >= 0) failures.push(`${label}: differs at byte ${at} (${ours.length} vs ${theirs.length} bytes)`);
}

// One case: the module's frame against `hsr render` with the same request.
function compareRender(label, sceneSpec, request, flags) {
  const dir = path.join(work, 'case');
  fs.rmSync(dir, {recursive: true, force: true});
  let frame = null, ourError = null;
  try {
    frame = hsr.render({width: WIDTH, height: HEIGHT, ...request});
  } catch (e) {
    if (!(e instanceof HsrError)) throw e;
    ourError = e.message;
  }
  const theirError = native(['render', sceneSpec, '--algorithm', request.algorithm, '--size', `${WIDTH}x${HEIGHT}`,
                             ...flags, '--output', 'color,depth,ids,overdraw', '-o', path.join(dir, 'frame.png'),
                             '--raw', path.join(dir, 'raw'), '-q']);
  ++compared;
  if (ourError || theirError) {
    // Refused by both (an option the algorithm does not take): the same reason
    if (!ourError || !theirError || !theirError.includes(ourError))
      failures.push(`${label}: module says "${ourError}", native says "${theirError}"`);
    return;
  }
  for (const kind of ['color', 'depth', 'ids', 'overdraw']) {
    const png = readPng(path.join(dir, `frame-${kind}.png`));
    const ours = frame.picture(kind);
    const rgb = new Uint8Array(WIDTH * HEIGHT * 3);
    for (let i = 0, j = 0; i < ours.length; i += 4, j += 3) rgb[j] = ours[i], rgb[j + 1] = ours[i + 1], rgb[j + 2] = ours[i + 2];
    same(`${label} ${kind} picture`, rgb, png.data);
  }
  same(`${label} depth`, new Uint8Array(frame.depth.buffer), readNpyData(path.join(dir, 'raw', 'depth.npy')));
  same(`${label} ids`, new Uint8Array(frame.ids.buffer), readNpyData(path.join(dir, 'raw', 'ids.npy')));
  same(`${label} overdraw`, new Uint8Array(frame.overdraw.buffer), readNpyData(path.join(dir, 'raw', 'overdraw.npy')));
}

const {algorithms} = hsr.catalogue();
const started = Date.now();

// Every scene, every algorithm, default controls
for (const spec of SCENES) {
  hsr.load(spec);
  for (const a of algorithms) compareRender(`${spec} ${a.name}`, spec, {algorithm: a.name}, []);
}
// The GL-style controls on the demo scene, for every algorithm that has the capability
hsr.load('demo');
for (const c of CONTROLS) {
  for (const a of algorithms) {
    if (c.capability && !a.capabilities.includes(c.capability)) continue;
    compareRender(`demo ${a.name} ${c.flags.join(' ')}`, 'demo', {algorithm: a.name, ...c.request}, c.flags);
  }
}
// The orbit camera: the page's request against the CLI's --eye/--target/--up
{
  const eye = [3.2, 2.1, -4.4], target = [0.1, 0.0, 0.2], up = [0, 1, 0];
  for (const name of ['zbuffer', 'raycast', 'warnock']) {
    compareRender(`demo ${name} orbit`, 'demo', {algorithm: name, camera: {eye, target, up, fov_deg: 45}},
                  ['--eye', eye.join(','), '--target', target.join(','), '--up', up.join(',')]);
  }
}
// The three front-ends accept and refuse the same values: the web module's half of
// tests/frontend/cases.json (the command line's is tests/cli/frontends_test.cpp, Python's
// tests/python/test_frontends.py). Options are the request's keys by the table's names; the
// size is width and height.
{
  const cases = JSON.parse(fs.readFileSync(new URL('../../tests/frontend/cases.json', import.meta.url)))
      .cases.filter((c) => (c.only || ['web']).includes('web'));
  hsr.load('demo');
  for (const c of cases) {
    const {size, ...options} = c.options;
    const [width, height] = size || [64, 48];
    let error = null;
    try {
      hsr.render({algorithm: 'zbuffer', width, height, ...options});
    } catch (e) {
      if (!(e instanceof HsrError)) throw e;
      error = e.message;
    }
    ++compared;
    const says = c.says && c.says.replace(/\{([a-z_]+)\}/g, '$1');
    if (says ? !(error || '').includes(says) : error !== null)
      failures.push(`options ${JSON.stringify(c.options)}: the module says "${error}", the case "${says || 'renders'}"`);
  }
}
// The explain steps: the same steps with the same captions as `hsr explain`
for (const a of algorithms.filter((a) => a.explain)) {
  const dir = path.join(work, `explain-${a.name}`);
  fs.rmSync(dir, {recursive: true, force: true});
  const why = native(['explain', a.name, 'demo', '--size', `${WIDTH}x${HEIGHT}`, '-o', dir, '-q']);
  ++compared;
  if (why) {
    failures.push(`explain ${a.name}: native refused: ${why}`);
    continue;
  }
  const ours = hsr.explain({algorithm: a.name, width: WIDTH, height: HEIGHT}).steps
      .map((s) => `${s.number}. **${s.name}**: ${s.caption}`);
  const theirs = fs.readFileSync(path.join(dir, 'steps.md'), 'utf8').split('\n')
      .filter((l) => /^\d+\. \*\*/.test(l)).map((l) => l.replace(/ \[picture\]\([^)]*\)$/, ''));
  if (JSON.stringify(ours) !== JSON.stringify(theirs))
    failures.push(`explain ${a.name}: ${ours.length} steps here, ${theirs.length} natively, or captions differ`);
}
// A dropped OBJ file: the module's reader against assimp's, by their pictures and ids
{
  const obj = [
    '# two quads and a triangle, in two objects',
    'o floor', 'v -2 0 -2', 'v 2 0 -2', 'v 2 0 2', 'v -2 0 2', 'f 1 4 3 2',
    'o block', 'v -0.5 0 0', 'v 0.5 0 0', 'v 0.5 1 0', 'v -0.5 1 0', 'v 0 1.5 0',
    'f 5//1 6//1 7//1 8//1', 'f -2 -1 -3',
  ].join('\n') + '\n';
  const file = path.join(work, 'dropped.obj');
  fs.writeFileSync(file, obj);
  hsr.loadObj(obj, 'dropped.obj');
  compareRender('dropped.obj zbuffer', file, {algorithm: 'zbuffer'}, []);
}

const seconds = ((Date.now() - started) / 1000).toFixed(1);
if (failures.length) {
  console.error(failures.slice(0, 40).join('\n'));
  console.error(`web module vs native: ${failures.length} of ${compared} cases differ`);
  process.exit(1);
}
console.log(`web module vs native: ${compared} cases, ${bytes} bytes, all identical (${seconds} s)`);
