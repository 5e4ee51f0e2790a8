// `npm run bench`: times the core on generated meshes and prints figures (asserts nothing).
//
// For each size, a child process (so every run starts from a fresh WebAssembly memory)
// generates a closed, fuselage-like binary STL, then measures in one process:
//   - Mesh.fromStl (parse, weld, adjacency, winding, face geometry)
//   - mesh.segment with the paper's parameters (α 0.35 rad, θmax 1 rad, ε 10 %)
//   - three.js STLLoader.parse of the same bytes (a plain, unwelded parse) for comparison
//   - WebAssembly memory after import + segmentation, per triangle
// Times are medians of several runs after a warm-up.
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const SIZES = [20_000, 200_000, 1_000_000, 2_000_000];

/** A closed surface of revolution (nose, barrel, tail cone) with about `target` triangles. */
export function fuselageStl(target) {
  const around = Math.max(8, Math.round(Math.sqrt(target)));
  const along = Math.max(4, Math.round(target / (2 * around)));
  const length = 40, radius = 2.5;
  const ring = (j) => {
    const t = j / along;
    // Radius profile: rounded nose, constant barrel, tapering tail; exact 0 at both ends.
    const r = t === 0 || t === 1 ? 0 : radius * Math.min(1, Math.sqrt(t / 0.12), Math.sqrt((1 - t) / 0.25));
    return [t * length, r];
  };
  const point = (i, j) => {
    const [x, r] = ring(j);
    const a = (2 * Math.PI * (i % around)) / around;
    return [x, r * Math.cos(a), r * Math.sin(a)];
  };
  const tris = [];
  for (let j = 0; j < along; j++) {
    for (let i = 0; i < around; i++) {
      const a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
      if (j > 0) tris.push([a, c, b]);
      if (j < along - 1) tris.push([a, d, c]);
    }
  }
  const bytes = new Uint8Array(84 + 50 * tris.length);
  const view = new DataView(bytes.buffer);
  view.setUint32(80, tris.length, true);
  let o = 84;
  for (const t of tris) {
    o += 12; // normal left zero: the core recomputes it
    for (const p of t) for (const c of p) { view.setFloat32(o, c, true); o += 4; }
    o += 2;
  }
  return bytes;
}

function median(xs) {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

async function runOne(target) {
  const { initSync, Mesh, wasmMemoryBytes } = await import(join(root, 'dist/pkg/skinpath.js'));
  const { STLLoader } = await import('three/examples/jsm/loaders/STLLoader.js');
  initSync({ module: readFileSync(join(root, 'dist/pkg/skinpath_bg.wasm')) });
  const bytes = fuselageStl(target);
  const triangles = (bytes.length - 84) / 50;
  const params = { angleThreshold: 0.35, thetaMax: 1, minAreaRatio: 0.1 };
  const runs = triangles > 500_000 ? 3 : 7;

  // First run: memory of one import + segmentation from a fresh module.
  let mesh = Mesh.fromStl(bytes);
  let seg = mesh.segment(params);
  const memory = wasmMemoryBytes();
  const patches = seg.patchCount;
  seg.free(); mesh.free();

  const parse = [], segment = [], three = [];
  const loader = new STLLoader();
  for (let r = 0; r < runs; r++) {
    globalThis.gc?.();
    let t = performance.now();
    const g = loader.parse(bytes.buffer);
    three.push(performance.now() - t);
    g.dispose();
    globalThis.gc?.();
    t = performance.now();
    mesh = Mesh.fromStl(bytes);
    parse.push(performance.now() - t);
    t = performance.now();
    seg = mesh.segment(params);
    segment.push(performance.now() - t);
    seg.free(); mesh.free();
  }
  const [p, s, l] = [median(parse), median(segment), median(three)];
  return { triangles, fromStl: p, segment: s, stlLoader: l, ratio: (p + s) / l,
    bytesPerTriangle: memory / triangles, memoryMiB: memory / 2 ** 20, patches };
}

const isMain = process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1];
const sizeArg = !isMain ? -1 : process.argv.indexOf('--size');
if (sizeArg > 0) {
  const result = await runOne(Number(process.argv[sizeArg + 1]));
  process.stdout.write(JSON.stringify(result));
} else if (isMain) {
  const sizes = process.argv.slice(2).map(Number).filter(Boolean);
  console.log('skinpath benchmark (Node %s): generated closed fuselage meshes, binary STL', process.version);
  console.log('triangles   fromStl ms  segment ms  STLLoader ms  (fromStl+segment)/STLLoader  wasm MiB  bytes/triangle  patches');
  for (const size of sizes.length ? sizes : SIZES) {
    const out = execFileSync(process.execPath, ['--expose-gc', '--max-old-space-size=8192',
      fileURLToPath(import.meta.url), '--size', String(size)], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
    const r = JSON.parse(out);
    console.log(
      `${String(r.triangles).padStart(9)}  ${r.fromStl.toFixed(1).padStart(10)}  ${r.segment.toFixed(1).padStart(10)}` +
      `  ${r.stlLoader.toFixed(1).padStart(12)}  ${r.ratio.toFixed(2).padStart(27)}` +
      `  ${r.memoryMiB.toFixed(1).padStart(8)}  ${r.bytesPerTriangle.toFixed(1).padStart(14)}  ${String(r.patches).padStart(7)}`);
  }
}
