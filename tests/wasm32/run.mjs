// Runs the determinism suite's wasm32 build (tests/wasm32, built by scripts/wasm32) and prints
// its report: node tests/wasm32/run.mjs FILE.wasm. The module imports nothing.
import { readFileSync } from "node:fs";

const file = process.argv[2];
if (!file) {
  console.error("usage: node run.mjs FILE.wasm");
  process.exit(2);
}
const { instance } = await WebAssembly.instantiate(readFileSync(file), {});
const { memory, volley_suite, volley_suite_len } = instance.exports;
const ptr = volley_suite();
const len = volley_suite_len();
process.stdout.write(new TextDecoder().decode(new Uint8Array(memory.buffer, ptr, len)));
