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
  }

  text(len) {
    if (!len) return "";
    return decoder.decode(new Uint8Array(this.x.memory.buffer, this.x.taxel_text_ptr(), len));
  }

  // One code per actuator (row-major).
  lateroFrame(tick, x, y) {
    const at = this.x.taxel_latero_frame(tick, x, y);
    const n = this.info.rows * this.info.cols;
    return at ? new Uint16Array(this.x.memory.buffer, at, n).slice() : new Uint16Array(0);
  }

  // One height per pin of the display, and the viewport's top-left pin.
  pinsFrame(tick, x, y) {
    const at = this.x.taxel_pins_frame(tick, x, y);
    const n = this.info.rows * this.info.cols;
    const view = this.x.taxel_pins_view();
    return {
      pins: at ? new Uint8Array(this.x.memory.buffer, at, n).slice() : new Uint8Array(0),
      col: view & 0xffff,
      row: view >>> 16,
    };
  }

  // Left, down, right intensities, period (ms), height (mm), on a step (1).
  fingerSample(tick, x, y, contact) {
    const at = this.x.taxel_finger_sample(tick, x, y, contact ? 1 : 0);
    return at ? new Float32Array(this.x.memory.buffer, at, 6).slice() : new Float32Array(0);
  }

  // One amplitude (0..1) per actuator.
  gridFrame(tick) {
    const at = this.x.taxel_grid_frame(tick);
    const n = this.info.rows * this.info.cols;
    return at ? new Float32Array(this.x.memory.buffer, at, n).slice() : new Float32Array(0);
  }

  nameAt(x, y) {
    return this.text(this.x.taxel_name_at(x, y));
  }

  idAt(x, y) {
    return this.text(this.x.taxel_id_at(x, y));
  }
}
