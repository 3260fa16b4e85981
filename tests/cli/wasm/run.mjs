// Runs the studio's WebAssembly module in Node.js (V8, the engine of the
// browsers the studio serves) for `tests/cli/studio_wasm.rs`: one JSON
// request a line on stdin, one JSON answer a line on stdout.
//   {"op":"new"}                          a fresh instance of the module
//   {"op":"call","name":N,"args":[...]}   an export's result (null for none)
//   {"op":"write","at":A,"b64":B}         bytes into the instance's memory
//   {"op":"read","at":A,"len":L}          bytes out of it, in base64
// An error (a trap, a missing export) answers {"err": message}.
import { readFileSync } from 'node:fs';
import { createInterface } from 'node:readline';

const module = await WebAssembly.compile(readFileSync(process.argv[2]));
let instance = await WebAssembly.instantiate(module, {});
const memory = () => new Uint8Array(instance.exports.memory.buffer);

for await (const line of createInterface({ input: process.stdin, crlfDelay: Infinity })) {
  let answer;
  try {
    const r = JSON.parse(line);
    let ok = null;
    if (r.op === 'new') {
      instance = await WebAssembly.instantiate(module, {});
    } else if (r.op === 'call') {
      const f = instance.exports[r.name];
      if (typeof f !== 'function') throw new Error(`no export ${r.name}`);
      const v = f(...r.args);
      ok = v === undefined ? null : v;
    } else if (r.op === 'write') {
      memory().set(Buffer.from(r.b64, 'base64'), r.at);
    } else if (r.op === 'read') {
      ok = Buffer.from(memory().subarray(r.at, r.at + r.len)).toString('base64');
    } else {
      throw new Error(`unknown op ${r.op}`);
    }
    answer = { ok };
  } catch (e) {
    answer = { err: String(e) };
  }
  process.stdout.write(JSON.stringify(answer) + '\n');
}
