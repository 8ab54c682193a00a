// hsr's WebAssembly module (module/hsr_web.cpp) as a JavaScript class, for the page (app.js)
// and the node tests alike. Every answer is copied out of the module's memory, so it stays
// valid after the next call.
//
//   const hsr = new Hsr(await createHsr());
//   hsr.load('spheres:2000');
//   const frame = hsr.render({algorithm: 'warnock', width: 320, height: 240});
//   frame.picture('color')   // Uint8ClampedArray, RGBA, ready for ImageData
//   frame.ids                // Uint32Array, 0xFFFFFFFF where nothing was drawn

export class HsrError extends Error {}

export class Hsr {
  constructor(module) {
    this.m = module;
  }

  // Throws the module's one-line reason when a call failed.
  check(failed) {
    if (failed) throw new HsrError(this.m.ccall('hsr_web_error', 'string', [], []));
  }

  json(name, types = [], args = []) {
    const text = this.m.ccall(name, 'string', types, args);
    this.check(!text);
    return JSON.parse(text);
  }

  // {scenes: [{name, summary}], algorithms: [{name, summary, source, capabilities, explain, ...}]}
  catalogue() {
    return this.json('hsr_web_catalogue');
  }

  load(spec) {
    this.check(this.m.ccall('hsr_web_load', 'number', ['string'], [spec]) !== 0);
    return this.scene({});
  }

  loadObj(text, name) {
    this.check(this.m.ccall('hsr_web_load_obj', 'number', ['string', 'string'], [text, name]) !== 0);
    return this.scene({});
  }

  // The loaded scene's counts, bounds and the camera hsr frames it with at request's size.
  scene(request) {
    return this.json('hsr_web_scene', ['string'], [JSON.stringify(request)]);
  }

  bytes(pointer, length) {
    this.check(!pointer);
    return this.m.HEAPU8.slice(pointer, pointer + length);
  }

  // Renders; the frame's buffers and statistics, copied.
  render(request) {
    this.check(this.m.ccall('hsr_web_render', 'number', ['string'], [JSON.stringify(request)]) !== 0);
    const width = this.m._hsr_web_width(), height = this.m._hsr_web_height(), n = width * height;
    const depth = new Float32Array(this.bytes(this.m._hsr_web_depth(), 4 * n).buffer);
    const ids = new Uint32Array(this.bytes(this.m._hsr_web_ids(), 4 * n).buffer);
    const overdraw = new Uint32Array(this.bytes(this.m._hsr_web_overdraw(), 4 * n).buffer);
    const stats = this.json('hsr_web_stats');
    const pictures = {};
    for (const kind of ['color', 'depth', 'ids', 'overdraw']) {
      const p = this.m.ccall('hsr_web_picture', 'number', ['string'], [kind]);
      pictures[kind] = new Uint8ClampedArray(this.bytes(p, 4 * n).buffer);
    }
    return {width, height, depth, ids, overdraw, stats, picture: (kind) => pictures[kind]};
  }

  // The algorithm's steps as `hsr explain` shows them: [{number, name, caption, outlines,
  // color, depth}], pictures RGBA at the request's size; and the finished frame.
  explain(request) {
    const count = this.m.ccall('hsr_web_explain', 'number', ['string'], [JSON.stringify(request)]);
    this.check(count < 0);
    const width = this.m._hsr_web_width(), height = this.m._hsr_web_height(), n = width * height;
    const steps = [];
    for (let i = 0; i < count; ++i) {
      const step = this.json('hsr_web_step', ['number'], [i]);
      for (const kind of ['color', 'depth']) {
        const p = this.m.ccall('hsr_web_step_picture', 'number', ['number', 'string'], [i, kind]);
        step[kind] = new Uint8ClampedArray(this.bytes(p, 4 * n).buffer);
      }
      steps.push(step);
    }
    return {width, height, steps};
  }
}
