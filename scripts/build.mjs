// Builds the complete static site into dist/:
//   dist/pkg/skinpath.js + skinpath_bg.wasm   wasm-pack --target web, release, then wasm-opt
//   dist/*                                    the page sources from www/
//   dist/vendor/…                             third-party modules listed in www/vendor.json
// `npm run build` runs scripts/setup.sh first; run directly, a missing tool is named in one line.
import { execFileSync, spawnSync } from 'node:child_process';
import { appendFileSync, cpSync, mkdirSync, readFileSync, readdirSync, rmSync, existsSync, statSync } from 'node:fs';
import { delimiter, dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..');
// Where rustup and `cargo install` put wasm-pack and wasm-bindgen, often missing from PATH.
if (process.env.HOME) process.env.PATH = `${join(process.env.HOME, '.cargo', 'bin')}${delimiter}${process.env.PATH ?? ''}`;
const dist = join(root, 'dist');
const pkg = join(dist, 'pkg');

/** Stops the build with one line (no stack trace). */
function fail(message) {
  console.error(`build: ${message}`);
  process.exit(1);
}

function run(cmd, args) {
  console.error(`build: ${cmd} ${args.join(' ')}`);
  try {
    execFileSync(cmd, args, { cwd: root, stdio: 'inherit' });
  } catch (error) {
    const name = cmd.split(/[\\/]/).pop();
    if (error.code === 'ENOENT') fail(`${name} is not installed; run \`npm run setup\` (bash scripts/setup.sh) first`);
    fail(`${name} failed (${error.status === null ? `signal ${error.signal}` : `exit status ${error.status}`}); its output is above`);
  }
}

// Where a call with an argument too many most likely meant to go instead.
const EXTRA_ARGUMENT_HINTS = {
  correctHoles: 'to project the corrected holes onto a panel, call mesh.correctHoles(params) on the Mesh',
};

// What each exported class's use after free() should tell the user to do instead.
const AGAIN = {
  Mesh: 'load the file again', Segmentation: 'segment the mesh again',
  DistanceField: 'compute the distance again', ToolPath: 'build the tool path again',
};
/** How each class without a constructor is made (`new Mesh()` gives an empty object). */
const MADE_BY = {
  Mesh: 'Mesh.fromStl(bytes) or new StlReader(size).finish()', Segmentation: 'mesh.segment(params)',
  SprayPlan: 'mesh.planSpray(params, faces)', DistanceField: 'mesh.geodesicDistance(source, options)',
  ToolPath: 'field.toolPath(spacing, options)',
};

/**
 * Appends to the wasm-bindgen glue a guard for every exported class, so that
 * - a method or getter of a freed object throws `Error("this Mesh was freed (free() was
 *   called); load the file again")` instead of wasm-bindgen's "null pointer passed to rust";
 * - free() twice does nothing the second time;
 * - free() called while a method of the same object is running (from its onProgress
 *   callback) waits until that method returns, instead of failing inside wasm;
 * - calls nested through onProgress callbacks are refused beyond a small depth;
 * - a call of an exported function, method or static method with more arguments than it
 *   declares throws `Error("correctHoles() takes at most 1 argument (params), got 2: …")` unless the
 *   extra ones are undefined (wasm-bindgen would drop them without a word).
 * It relies on wasm-bindgen's `__wbg_ptr` field and `free()` method, checked here so that a
 * wasm-bindgen upgrade that renames them fails the build rather than the guard.
 */
function guardGlue(file) {
  const glue = readFileSync(file, 'utf8');
  const classes = [...glue.matchAll(/^export class (\w+) \{/gm)].map((m) => m[1]);
  if (classes.length === 0 || !glue.includes('this.__wbg_ptr') || !/^\s+free\(\) \{/m.test(glue)) {
    fail(`${file} does not look like wasm-bindgen 0.2 glue (exported classes with __wbg_ptr and free()); update guardGlue in scripts/build.mjs`);
  }
  const constructed = new Set([...glue.matchAll(/^export class (\w+) \{[\s\S]*?^\}/gm)]
    .filter((m) => /^ {4}constructor\(/m.test(m[0])).map((m) => m[1]));
  for (const c of classes) {
    if (!constructed.has(c) && !MADE_BY[c]) fail(`${file}: class ${c} has no constructor and no entry in MADE_BY (scripts/build.mjs)`);
  }
  const calls = classes.map((c) => `guardFreed(${c}, ${JSON.stringify(c)}, ${JSON.stringify(AGAIN[c] ?? `create a new ${c}`)}, ${JSON.stringify(constructed.has(c) ? null : MADE_BY[c])});`);
  // Exported functions are function declarations: reassigning one updates the live export.
  const functions = [...glue.matchAll(/^export function (\w+)\(/gm)].map((m) => m[1]);
  if (functions.length === 0) fail(`${file} exports no function; update guardGlue in scripts/build.mjs`);
  const wrapped = functions.map((f) => `${f} = checkedArity(${f}, ${JSON.stringify(f)});`);
  appendFileSync(file, `
// Added by scripts/build.mjs (guardGlue): use after free() names the problem, free() is
// idempotent, free() from inside a running method of the same object is deferred, and calls
// nest through onProgress callbacks at most MAX_NESTING deep (unbounded nesting would end in
// a stack overflow thrown inside wasm, which leaves Rust borrows taken); a call with more
// arguments than declared is refused unless the extra ones are undefined.
const MAX_NESTING = 4;
let nesting = 0;
const EXTRA_ARGUMENT_HINTS = ${JSON.stringify(EXTRA_ARGUMENT_HINTS)};
function checkArgs(f, what, args) {
  if (args.length <= f.length || args.slice(f.length).every((a) => a === undefined)) return;
  const declared = /^[^(]*\\(([^)]*)\\)/.exec(String(f))?.[1].trim() ?? '';
  const n = f.length;
  const hint = EXTRA_ARGUMENT_HINTS[what];
  throw new Error(\`\${what}() takes \${n === 0 ? 'no arguments' : \`at most \${n} argument\${n === 1 ? '' : 's'} (\${declared})\`}, got \${args.length}: \${hint ?? 'the extra ones would be ignored'}\`);
}
// A wrapper keeps the name and declared arity (\`length\`) of the function it wraps.
function like(wrapper, f) {
  Object.defineProperty(wrapper, 'name', { value: f.name });
  Object.defineProperty(wrapper, 'length', { value: f.length });
  return wrapper;
}
function checkedArity(f, what) {
  return like(function (...args) {
    checkArgs(f, what, args);
    return f.apply(this, args);
  }, f);
}
function guardFreed(cls, name, again, madeBy) {
  const proto = cls.prototype;
  const running = new WeakMap();
  const freeLater = new WeakSet();
  const rawFree = proto.free;
  // free() sets the pointer to 0; an object made with \`new\` of a class the engine makes
  // itself never had one.
  const freed = (self) => new Error(madeBy && self.__wbg_ptr === undefined
    ? \`this \${name} was made with new \${name}(), which gives an empty object: use \${madeBy}\`
    : \`this \${name} was freed (free() was called); \${again}\`);
  const enter = (what) => {
    if (nesting >= MAX_NESTING) {
      throw new Error(\`\${name}.\${what}() was called from an onProgress callback \${nesting} calls deep; call it after the outer call returns\`);
    }
    nesting++;
  };
  const guardStatic = (f, what) => like(function (...args) {
    checkArgs(f, \`\${name}.\${what}\`, args);
    enter(what);
    try {
      return f.apply(this, args);
    } finally {
      nesting--;
    }
  }, f);
  const guard = (f, what) => like(function (...args) {
    if (!this.__wbg_ptr || freeLater.has(this)) throw freed(this);
    checkArgs(f, \`\${name}.\${what}\`, args);
    enter(what);
    running.set(this, (running.get(this) ?? 0) + 1);
    try {
      return f.apply(this, args);
    } finally {
      nesting--;
      const n = running.get(this) - 1;
      if (n > 0) running.set(this, n);
      else {
        running.delete(this);
        if (freeLater.delete(this)) rawFree.call(this);
      }
    }
  }, f);
  for (const key of Object.getOwnPropertyNames(proto)) {
    if (key === 'constructor' || key === 'free' || key.startsWith('__')) continue;
    const d = Object.getOwnPropertyDescriptor(proto, key);
    if (typeof d.value === 'function') d.value = guard(d.value, key);
    if (d.get) d.get = guard(d.get, key);
    if (d.set) d.set = guard(d.set, key);
    Object.defineProperty(proto, key, d);
  }
  for (const key of Object.getOwnPropertyNames(cls)) {
    const d = Object.getOwnPropertyDescriptor(cls, key);
    if (key.startsWith('__') || typeof d.value !== 'function') continue;
    d.value = guardStatic(d.value, key);
    Object.defineProperty(cls, key, d);
  }
  const free = function free() {
    if (running.get(this)) freeLater.add(this);
    else if (this.__wbg_ptr) rawFree.call(this);
  };
  proto.free = free;
  if (typeof Symbol.dispose === 'symbol' && proto[Symbol.dispose]) proto[Symbol.dispose] = free;
}
${calls.join('\n')}
${wrapped.join('\n')}
`);
  console.error(`build: guarded ${classes.join(', ')} against use after free(), and every export against extra arguments`);
}

/** Fails at once, in one line, when a tool the build needs is missing (a fresh clone). */
function need(cmd) {
  if (spawnSync(cmd, ['--version'], { stdio: 'ignore' }).error?.code === 'ENOENT') {
    fail(`${cmd.split(/[\\/]/).pop()} is not installed; run \`npm run setup\` (bash scripts/setup.sh) first`);
  }
}

function buildWasm() {
  const localWasmOpt = join(root, 'node_modules', '.bin', 'wasm-opt');
  const wasmOpt = existsSync(localWasmOpt) ? localWasmOpt : 'wasm-opt';
  need('wasm-pack');
  need('wasm-bindgen');
  need(wasmOpt);
  run('wasm-pack', ['build', '--release', '--target', 'web', '--out-dir', pkg, '--out-name', 'skinpath',
    '--no-pack', '--', '--features', 'wasm']);
  const wasm = join(pkg, 'skinpath_bg.wasm');
  const before = statSync(wasm).size;
  // -O3 inlines every function with one caller, whatever its size, by default: the spray
  // planner's stages then become one function of several thousand lines, which the engines
  // compile worse (the spray search 15-25 % slower than without wasm-opt at all). Bounding
  // it keeps the rest of -O3 (the geodesics gain 10-15 % from it).
  run(wasmOpt, ['-O3', '--one-caller-inline-max-function-size', '200', wasm, '-o', wasm]);
  console.error(`build: wasm ${before} -> ${statSync(wasm).size} bytes after wasm-opt`);
  guardGlue(join(pkg, 'skinpath.js'));
}

function copySite() {
  // Everything but the wasm package is rewritten, so files removed from www/ (or from
  // vendor.json) do not linger in dist/ from an earlier build.
  mkdirSync(dist, { recursive: true });
  for (const name of readdirSync(dist)) if (name !== 'pkg') rmSync(join(dist, name), { recursive: true, force: true });
  cpSync(join(root, 'www'), dist, { recursive: true, filter: (src) => !src.endsWith('vendor.json') });
  const manifest = join(root, 'www', 'vendor.json');
  if (!existsSync(manifest)) return;
  // vendor.json: { "node_modules path": "dist/vendor path" } for every third-party file the page loads.
  const files = JSON.parse(readFileSync(manifest, 'utf8'));
  for (const [from, to] of Object.entries(files)) {
    const src = join(root, 'node_modules', from);
    if (!existsSync(src)) fail(`vendor.json names ${from}, which is not in node_modules; run \`npm run setup\` (bash scripts/setup.sh) first`);
    const dst = join(dist, 'vendor', to);
    mkdirSync(dirname(dst), { recursive: true });
    cpSync(src, dst, { recursive: true });
  }
}

const onlySite = process.argv.includes('--site-only');
if (!onlySite) {
  rmSync(pkg, { recursive: true, force: true });
  mkdirSync(dist, { recursive: true });
  buildWasm();
}
copySite();
console.error(`build: site written to ${dist}`);
