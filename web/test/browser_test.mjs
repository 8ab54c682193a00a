// The page in a real browser: a local server on 127.0.0.1 (started here, stopped by its process
// id), headless Chromium loads the page in its test mode, which renders the demo with every
// algorithm in turn and reads each picture back from its canvas; those bytes must equal the
// native `hsr render` PNG's. A screenshot of the page (its explain view at step 7) is kept as the
// test's artifact; the README's picture (docs/web-page.png) is one.
//
//   node web/test/browser_test.mjs SITE_DIR NATIVE_HSR ARTIFACT_DIR

import {execFileSync, spawn} from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';

import {firstDifference, readPng} from './native_files.mjs';

const [site, nativeHsr, artifacts] = process.argv.slice(2);
if (!site || !nativeHsr || !artifacts) {
  console.error('usage: browser_test.mjs SITE_DIR NATIVE_HSR ARTIFACT_DIR');
  process.exit(2);
}
fs.mkdirSync(artifacts, {recursive: true});
// The two algorithms the page opens with: they disagree on the demo (painter-naive draws the
// cyclic polygons wrong, on purpose), so the screenshot's disagreement view shows something
const ALGORITHMS = ['warnock', 'painter-naive'], SIZE = [320, 240];

// The server: Python's, on a port the system picks, its address read from what it prints
const server = spawn('python3', ['-u', '-m', 'http.server', '--bind', '127.0.0.1', '0', '--directory', site],
                     {stdio: ['ignore', 'pipe', 'pipe']});
const stop = () => {
  try {
    process.kill(server.pid);
  } catch {
    // already gone
  }
};
process.on('exit', stop);

function chromium(args) {
  // Headless, software-drawn, no sandbox (CI runs as root), bounded in time
  return execFileSync('chromium', ['--headless=new', '--no-sandbox', '--disable-gpu', '--hide-scrollbars',
                                   '--virtual-time-budget=60000', ...args],
                      {timeout: 180000, maxBuffer: 64 << 20, stdio: ['ignore', 'pipe', 'ignore']}).toString();
}

try {
  const port = await new Promise((resolve, reject) => {
    let seen = '';
    server.stdout.on('data', (d) => {
      seen += d;
      const m = seen.match(/port (\d+)/);
      if (m) resolve(Number(m[1]));
    });
    server.on('exit', (code) => reject(new Error(`the server stopped (${code})`)));
    setTimeout(() => reject(new Error('the server did not start in 20 s')), 20000);
  });
  const base = `http://127.0.0.1:${port}/index.html`;
  const query = `scene=demo&algorithms=${ALGORITHMS.join(',')}&size=${SIZE.join('x')}`;

  const dom = chromium(['--dump-dom', `${base}?test=all&${query}`]);
  const m = dom.match(/<pre id="test-result"[^>]*>([^<]*)<\/pre>/);
  if (!m || !m[1]) throw new Error('the page wrote no test result (did the module load?)');
  const result = JSON.parse(m[1].replaceAll('&amp;', '&'));
  const failures = [];
  const names = Object.keys(result);
  if (names.length < 12) failures.push(`the page drew ${names.length} algorithms: ${names.join(', ')}`);
  for (const name of names) {
    const got = result[name];
    const png = path.join(artifacts, `native-${name}.png`);
    execFileSync(nativeHsr, ['render', 'demo', '--algorithm', name, '--size', SIZE.join('x'), '-o', png, '-q']);
    const want = readPng(png);
    const rgba = Buffer.from(got.rgba, 'base64');
    const rgb = new Uint8Array(want.width * want.height * 3);
    let opaque = true;
    for (let i = 0, j = 0; i < rgba.length; i += 4, j += 3) {
      rgb[j] = rgba[i], rgb[j + 1] = rgba[i + 1], rgb[j + 2] = rgba[i + 2];
      opaque &&= rgba[i + 3] === 255;
    }
    const at = got.width === want.width && got.height === want.height ? firstDifference(rgb, want.data) : 0;
    if (at >= 0 || !opaque) failures.push(`${name}: the canvas differs from the native PNG at byte ${at}`);
    else console.log(`browser: ${name.padEnd(16)} canvas ${got.width}x${got.height} = the native PNG (${got.status})`);
  }
  // The page as a visitor sees it, kept for people to look at
  const shot = path.join(artifacts, 'page.png');
  chromium([`--screenshot=${shot}`, '--window-size=1500,1300', `${base}?${query}&step=7`]);
  if (!fs.existsSync(shot) || fs.statSync(shot).size < 10000) failures.push('no screenshot of the page');
  if (failures.length) {
    console.error(failures.join('\n'));
    process.exitCode = 1;
  } else {
    console.log(`browser: the page's canvases equal the native PNGs; screenshot ${shot}`);
  }
} catch (e) {
  console.error(`browser test: ${e.message}`);
  process.exitCode = 1;
} finally {
  stop();
}
