// The bundle player: taxel's runtime compiled to WebAssembly (runtime-wasm/).
// This file only moves numbers and bytes across the module's C ABI; every
// frame and every name comes from the Rust runtime.

const decoder = new TextDecoder();

export class Player {
  // Compiles the module once; each bundle gets a fresh instance.
  static async compile(url) {
    const response = await fetch(url);
    const bytes = await response.arrayBuffer();
    return WebAssembly.compile(bytes);
  }

  // Plays `bytes` (an ArrayBuffer holding a bundle); throws with the runtime's reason.
  static async load(module, bytes) {
    const instance = await WebAssembly.instantiate(module, {});
    const p = new Player(instance.exports);
    const at = p.x.taxel_input(bytes.byteLength);
    new Uint8Array(p.x.memory.buffer, at, bytes.byteLength).set(new Uint8Array(bytes));
    if (p.x.taxel_load() !== 0) {
      throw new Error(p.text(p.x.taxel_text_len()));
    }
    p.info = JSON.parse(p.text(p.x.taxel_info()));
    return p;
  }

  constructor(exports) {
    this.x = exports;
    // Views of the module's frame buffers, made once and kept: a frame is
    // read in place, with no copy and no allocation per tick. A view is
    // made again only when the module's memory has grown (growing it
    // detaches the old buffer) or the buffer moved.
    this.views = new Map();
  }

  // A view of `n` elements of `Type` at `at` in the module's memory, reused
  // from call to call.
  view(Type, at, n) {
    if (!at) return new Type(0);
    let v = this.views.get(Type);
    if (!v || v.buffer !== this.x.memory.buffer || v.byteOffset !== at || v.length !== n) {
      v = new Type(this.x.memory.buffer, at, n);
      this.views.set(Type, v);
    }
    return v;
  }

  text(len) {
    if (!len) return "";
    return decoder.decode(new Uint8Array(this.x.memory.buffer, this.x.taxel_text_ptr(), len));
  }

  // One code per actuator (row-major): a view of the module's buffer, valid
  // until the next call (copy it to keep it).
  lateroFrame(tick, x, y) {
    return this.view(Uint16Array, this.x.taxel_latero_frame(tick, x, y), this.info.rows * this.info.cols);
  }

  // One height per pin of the display (a view, as above), and the viewport's top-left pin.
  pinsFrame(tick, x, y) {
    const pins = this.view(Uint8Array, this.x.taxel_pins_frame(tick, x, y), this.info.rows * this.info.cols);
    const view = this.x.taxel_pins_view();
    return { pins, col: view & 0xffff, row: view >>> 16 };
  }

  // Left, down, right intensities, period (ms), height (mm), on a step (1) (a view).
  fingerSample(tick, x, y, contact) {
    return this.view(Float32Array, this.x.taxel_finger_sample(tick, x, y, contact ? 1 : 0), 6);
  }

  // One amplitude (0..1) per actuator (a view).
  gridFrame(tick) {
    return this.view(Float32Array, this.x.taxel_grid_frame(tick), this.info.rows * this.info.cols);
  }

  nameAt(x, y) {
    return this.text(this.x.taxel_name_at(x, y));
  }

  idAt(x, y) {
    return this.text(this.x.taxel_id_at(x, y));
  }
}
