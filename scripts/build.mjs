// Builds the complete static site into dist/:
//   dist/pkg/skinpath.js + skinpath_bg.wasm   wasm-pack --target web, release, then wasm-opt
//   dist/*                                    the page sources from www/
//   dist/vendor/…                             third-party modules listed in www/vendor.json
// Run through `npm run build` so node_modules/.bin (binaryen's wasm-opt) is on PATH.
import { execFileSync } from 'node:child_process';
import { cpSync, mkdirSync, readFileSync, rmSync, existsSync, statSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const dist = join(root, 'dist');
const pkg = join(dist, 'pkg');

function run(cmd, args) {
  console.error(`build: ${cmd} ${args.join(' ')}`);
  execFileSync(cmd, args, { cwd: root, stdio: 'inherit' });
}

function buildWasm() {
  run('wasm-pack', ['build', '--release', '--target', 'web', '--out-dir', pkg, '--out-name', 'skinpath',
    '--no-pack', '--', '--features', 'wasm']);
  const wasm = join(pkg, 'skinpath_bg.wasm');
  const before = statSync(wasm).size;
  const wasmOpt = join(root, 'node_modules', '.bin', 'wasm-opt');
  run(existsSync(wasmOpt) ? wasmOpt : 'wasm-opt', ['-O3', wasm, '-o', wasm]);
  console.error(`build: wasm ${before} -> ${statSync(wasm).size} bytes after wasm-opt`);
}

function copySite() {
  cpSync(join(root, 'www'), dist, { recursive: true, filter: (src) => !src.endsWith('vendor.json') });
  const manifest = join(root, 'www', 'vendor.json');
  if (!existsSync(manifest)) return;
  // vendor.json: { "node_modules path": "dist/vendor path" } for every third-party file the page loads.
  const files = JSON.parse(readFileSync(manifest, 'utf8'));
  for (const [from, to] of Object.entries(files)) {
    const src = join(root, 'node_modules', from);
    if (!existsSync(src)) throw new Error(`vendor.json names ${from}, which is not in node_modules`);
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
