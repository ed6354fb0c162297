// Runs the determinism suite's wasm32 build (tests/wasm32, built by scripts/wasm32) and prints
// its report: node tests/wasm32/run.mjs FILE.wasm. The module must import nothing: the sim
// stepped, hashed and replayed needs no host (volley-sim's `web` feature, which reads the
// browser's clock through wasm-bindgen's glue, is off in this build).
import { readFileSync } from "node:fs";

const file = process.argv[2];
if (!file) {
  console.error("usage: node run.mjs FILE.wasm");
  process.exit(2);
}
const module = await WebAssembly.compile(readFileSync(file));
const imports = WebAssembly.Module.imports(module);
if (imports.length > 0) {
  const names = imports.map((i) => `${i.module}.${i.name}`).join(", ");
  console.error(`${file} imports ${imports.length} item(s) (${names}); the suite's module must import nothing`);
  process.exit(1);
}
const instance = await WebAssembly.instantiate(module, {});
const { memory, volley_suite, volley_suite_len } = instance.exports;
const ptr = volley_suite();
const len = volley_suite_len();
process.stdout.write(new TextDecoder().decode(new Uint8Array(memory.buffer, ptr, len)));
