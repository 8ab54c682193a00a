// Reading what the native hsr writes, for the web tests: PNG (8-bit grey, RGB or RGBA, any of
// the five row filters) and NumPy .npy (version 1.0, little-endian). Node's own zlib inflates.

import fs from 'node:fs';
import zlib from 'node:zlib';

// {width, height, channels, data: Uint8Array} of a PNG file.
export function readPng(path) {
  const bytes = fs.readFileSync(path);
  const signature = [137, 80, 78, 71, 13, 10, 26, 10];
  if (!signature.every((b, i) => bytes[i] === b)) throw new Error(`${path}: not a PNG`);
  let at = 8, width = 0, height = 0, channels = 0;
  const idat = [];
  while (at < bytes.length) {
    const length = bytes.readUInt32BE(at);
    const type = bytes.toString('latin1', at + 4, at + 8);
    const body = bytes.subarray(at + 8, at + 8 + length);
    if (type === 'IHDR') {
      width = body.readUInt32BE(0);
      height = body.readUInt32BE(4);
      if (body[8] !== 8 || body[12] !== 0) throw new Error(`${path}: only 8-bit, non-interlaced PNGs`);
      channels = {0: 1, 2: 3, 4: 2, 6: 4}[body[9]];
      if (!channels) throw new Error(`${path}: colour type ${body[9]} not read here`);
    } else if (type === 'IDAT') {
      idat.push(body);
    }
    at += 12 + length;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const data = new Uint8Array(stride * height);
  for (let y = 0; y < height; ++y) {
    const filter = raw[y * (stride + 1)];
    const row = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let x = 0; x < stride; ++x) {
      const a = x >= channels ? data[y * stride + x - channels] : 0;
      const b = y > 0 ? data[(y - 1) * stride + x] : 0;
      const c = x >= channels && y > 0 ? data[(y - 1) * stride + x - channels] : 0;
      let predictor = 0;
      if (filter === 1) predictor = a;
      else if (filter === 2) predictor = b;
      else if (filter === 3) predictor = (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      } else if (filter !== 0) throw new Error(`${path}: row filter ${filter}`);
      data[y * stride + x] = (row[x] + predictor) & 0xff;
    }
  }
  return {width, height, channels, data};
}

// The data bytes of a .npy file (after its header).
export function readNpyData(path) {
  const bytes = fs.readFileSync(path);
  if (bytes.toString('latin1', 1, 6) !== 'NUMPY') throw new Error(`${path}: not a .npy file`);
  const headerLength = bytes.readUInt16LE(8);
  return new Uint8Array(bytes.buffer, bytes.byteOffset + 10 + headerLength, bytes.length - 10 - headerLength);
}

// The first index where two byte arrays differ, -1 where they are equal (lengths included).
export function firstDifference(a, b) {
  if (a.length !== b.length) return Math.min(a.length, b.length);
  for (let i = 0; i < a.length; ++i) if (a[i] !== b[i]) return i;
  return -1;
}
