// Fails when the modules of src/wasm/ import each other in a circle (a → b → … → a).
// A module uses another when it names `super::<module>` or, through the re-exports of
// mod.rs, `super::<Name>` / `use super::{…, Name, …}`; mod.rs itself is the hub and left out.
import { readFileSync, readdirSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const dir = join(dirname(fileURLToPath(import.meta.url)), '..', 'src', 'wasm');
const modules = readdirSync(dir).filter((f) => f.endsWith('.rs') && f !== 'mod.rs').map((f) => f.slice(0, -3));
const hub = readFileSync(join(dir, 'mod.rs'), 'utf8');
// Name re-exported by mod.rs → the module it comes from.
const owner = new Map();
for (const [, from, names] of hub.matchAll(/^pub use (\w+)::\{?([\w, ]+)\}?;/gm)) {
  for (const name of names.split(',')) owner.set(name.trim(), from);
}
const uses = new Map();
for (const m of modules) {
  // Comments are left out, so a doc line naming a module is not a use.
  const text = readFileSync(join(dir, `${m}.rs`), 'utf8').replace(/\/\/.*$/gm, '');
  const out = new Set();
  for (const [, path] of text.matchAll(/super::(\{[^}]*\}|\w+)/g)) {
    for (const name of path.replace(/[{}]/g, '').split(',').map((s) => s.trim().split('::')[0])) {
      const target = modules.includes(name) ? name : owner.get(name);
      if (target && target !== m) out.add(target);
    }
  }
  uses.set(m, out);
}
// Depth-first search for a back edge.
const state = new Map();
const stack = [];
function visit(m) {
  state.set(m, 'open');
  stack.push(m);
  for (const n of uses.get(m)) {
    if (state.get(n) === 'open') {
      const circle = [...stack.slice(stack.indexOf(n)), n].join(' → ');
      console.error(`src/wasm/ modules import each other in a circle: ${circle}`);
      process.exit(1);
    }
    if (!state.has(n)) visit(n);
  }
  stack.pop();
  state.set(m, 'done');
}
for (const m of modules) if (!state.has(m)) visit(m);
console.error(`src/wasm/: ${modules.length} modules, no circular imports`);
