// The web module's speed against the native build's on one thread, warm frames on both sides:
// each scene and algorithm rendered 1 + REPEAT times by the module under node, and by
// `hsr render --threads 1 --views` with the same camera 1 + REPEAT times in one process; the
// first (cold: allocation and first touch) dropped, the frames' own total times (Stats.totalMs:
// the pipeline and the algorithm) compared as medians, with their ratio (WebAssembly / native).
//
//   node bench/bench_web.mjs BUILD_WASM_WEB_DIR NATIVE_HSR [REPEAT]

import {execFileSync} from 'node:child_process';
import fs from 'node:fs';
import {createRequire} from 'node:module';
import os from 'node:os';
import path from 'node:path';

import {Hsr} from '../web/hsr.js';

const [moduleDir, nativeHsr, repeatArg] = process.argv.slice(2);
if (!moduleDir || !nativeHsr) {
  console.error('usage: bench_web.mjs BUILD_WASM_WEB_DIR NATIVE_HSR [REPEAT]');
  process.exit(2);
}
const repeat = Number(repeatArg || 5);
const createHsr = createRequire(import.meta.url)(path.resolve(moduleDir, 'hsr_web.js'));
const hsr = new Hsr(await createHsr({wasmBinary: fs.readFileSync(path.join(moduleDir, 'hsr_web.wasm'))}));
const work = fs.mkdtempSync(path.join(os.tmpdir(), 'hsr-bench-web-'));
const median = (v) => [...v].sort((a, b) => a - b)[Math.floor(v.length / 2)];

const CASES = [
  ['spheres:100000', 'zbuffer'], ['spheres:100000', 'scanline'], ['spheres:100000', 'warnock'],
  ['spheres:100000', 'raycast'], ['spheres:10000', 'painter'], ['spheres:10000', 'bsp'],
  ['spheres:10000', 'octree'], ['spheres:10000', 'abuffer'], ['spheres:2000', 'weiler-atherton'],
  ['spheres:2000', 'roberts'],
];
const [W, H] = [640, 480];
console.log(`the web module (node ${process.version}) against native hsr, one thread, ${W}x${H}, warm frames, medians of ${repeat}`);
console.log('scene            algorithm          wasm ms   native ms   wasm / native');
for (const [scene, algorithm] of CASES) {
  hsr.load(scene);
  const ours = [];
  for (let i = 0; i <= repeat; ++i) ours.push(hsr.render({algorithm, width: W, height: H}).stats.total_ms);
  // The native side: the camera hsr frames the scene with, as many times, from one import
  const one = path.join(work, 'one.json'), views = path.join(work, 'views.json'), many = path.join(work, 'many.json');
  const run = (extra) => execFileSync(nativeHsr, ['render', scene, '--algorithm', algorithm, '--threads', '1',
                                                  '--output', 'none', '-q', ...extra]);
  run(['--size', `${W}x${H}`, '--stats', one]);
  fs.writeFileSync(views, JSON.stringify(Array(repeat + 1).fill(JSON.parse(fs.readFileSync(one, 'utf8')).camera)));
  run(['--views', views, '--stats', many]);
  const theirs = JSON.parse(fs.readFileSync(many, 'utf8')).views.map((v) => v.total_ms);
  const a = median(ours.slice(1)), b = median(theirs.slice(1));
  console.log(`${scene.padEnd(16)} ${algorithm.padEnd(16)} ${a.toFixed(1).padStart(9)} ${b.toFixed(1).padStart(11)} ${(a / b).toFixed(2).padStart(15)}`);
}
fs.rmSync(work, {recursive: true, force: true});
