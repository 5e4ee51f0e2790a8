// `npm run bench -- geodesic` (from bench.mjs): geodesic distance on doubly curved meshes against
// the analytic distance, each method side by side with fast marching.
//
// Cases (GEODESIC_CURVED_SIZES, default 500000,2000000 triangles):
//   - a spherical cap R 1000 mm, half-angle 1 rad, in rings of 6·i vertices, its rim as the
//     source: the distance of a point at polar angle θ is R·(1 − θ);
//   - the same cap from its section by the plane through its ring of vertices nearest to
//     θ = 0.6 (a plane-section source; fast marching gets that ring as a closed curve):
//     R·|θ − θs|;
//   - a sphere R 100 mm from a cube of n × n cells a face, projected equi-angularly, a point
//     source at its south pole: the great-circle distance.
// Each method runs in a child process (fresh WebAssembly memory): Mesh.fromStl, then
// mesh.geodesicDistance timed alone; max and mean |d − analytic| over the welded vertices.
// Times are medians of GEODESIC_CURVED_RUNS runs (default 3; a fresh process each), fast
// marching's the median of as many solves by one solver: single runs on a shared machine
// vary by a third. Three times per method: `cold`, the first call in a fresh process (it runs
// partly in the engine's baseline code and compiles meanwhile); `page`, the first call after
// the warm-up the page's worker runs once a model is open and what the Paths tool prepares
// when it is opened (www/worker/paths.js `prepare`: the surface a distance on the whole
// model starts from, as fast marching's solver is built before its solve, and the memory of
// the first distance, www/worker/warm-up.js): the Paths tool's first distance on a model;
// `warm`, the same call made again in the process (the surface kept from the first call),
// once the engine has compiled the hot code to optimised machine code and the memory is grown.
// `exact` is skipped above GEODESIC_EXACT_MAX triangles (default 100 000; it takes minutes
// there: n^1.6 growth). Fast marching: potpourri3d 1.4.0 `MeshFastMarchingDistanceSolver` on the
// same vertices (rounded to f32 like the STL) and source (the rim as a closed curve through its
// vertices; the pole vertex), in a Python virtual environment this script creates on first use
// in node_modules/.cache (python3 -m venv, pip install potpourri3d==1.4.0); when python3 or the
// install is not available it says so and leaves the column out.
import { execFileSync, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

const here = fileURLToPath(import.meta.url);
const root = join(dirname(here), '..');
const SIZES = (process.env.GEODESIC_CURVED_SIZES ?? '500000,2000000').split(',').map(Number);
const EXACT_MAX = Number(process.env.GEODESIC_EXACT_MAX ?? 100_000);
const RUNS = Math.max(1, Number(process.env.GEODESIC_CURVED_RUNS ?? 3));
const median = (xs) => { const s = [...xs].sort((a, b) => a - b); return s[(s.length - 1) >> 1]; };
const METHODS = ['accurate', 'fast', 'exact'];
const CAP_R = 1000;
const SPHERE_R = 100;
const VENV = join(root, 'node_modules', '.cache', 'skinpath-potpourri3d-1.4.0');

/** Spherical cap in `rings` rings (ring i: 6·i vertices at polar angle i/rings rad). */
function cap(target) {
  const rings = Math.max(2, Math.round(Math.sqrt(target / 6)));
  const pos = [0, 0, CAP_R];
  const start = [0];
  for (let i = 1; i <= rings; i++) {
    start.push(pos.length / 3);
    const th = i / rings;
    for (let k = 0; k < 6 * i; k++) {
      const ph = (2 * Math.PI * k) / (6 * i);
      pos.push(CAP_R * Math.sin(th) * Math.cos(ph), CAP_R * Math.sin(th) * Math.sin(ph), CAP_R * Math.cos(th));
    }
  }
  const tri = [];
  for (let i = 1; i <= rings; i++) {
    // Merge ring i − 1 (m vertices) and ring i (n) by azimuth; the pole is one vertex.
    const [m, n, a0, b0] = [i === 1 ? 1 : 6 * (i - 1), 6 * i, start[i - 1], start[i]];
    let [a, b] = [i === 1 ? 1 : 0, 0];
    while (a < m || b < n) {
      if (b < n && (a >= m || (b + 0.5) / n <= (a + 0.5) / m)) {
        tri.push(a0 + (a % m), b0 + (b % n), b0 + ((b + 1) % n));
        b++;
      } else {
        tri.push(a0 + (a % m), b0 + (b % n), a0 + ((a + 1) % m));
        a++;
      }
    }
  }
  const rim = Array.from({ length: 6 * rings }, (_, k) => start[rings] + k);
  const exact = (x, y, z) => CAP_R * (1 - Math.acos(Math.min(1, Math.max(-1, z / Math.hypot(x, y, z)))));
  // The ring nearest to θ = 0.6, for the plane-section case.
  const i0 = Math.round(0.6 * rings);
  const ring = Array.from({ length: 6 * i0 }, (_, k) => start[i0] + k);
  return { positions: Float64Array.from(pos, Math.fround), triangles: Uint32Array.from(tri), rim, exact, ring, theta: i0 / rings };
}

/** The cap from its section by the plane through its ring nearest to θ = 0.6 (sampled at the
 *  ring's vertices and where it crosses edges): distance R·|θ − θs|. */
function section(target) {
  const m = cap(target);
  const exact = (x, y, z) => CAP_R * Math.abs(Math.acos(Math.min(1, Math.max(-1, z / Math.hypot(x, y, z)))) - m.theta);
  return { ...m, exact };
}

/** Cube sphere: n × n cells a face (n even), 12·n² triangles; the south pole is a vertex. */
function sphere(target) {
  const n = 2 * Math.max(1, Math.round(Math.sqrt(target / 12) / 2));
  const index = new Map();
  const pos = [];
  const id = (c) => {
    const key = (c[0] * (n + 1) + c[1]) * (n + 1) + c[2];
    let v = index.get(key);
    if (v === undefined) {
      const t = c.map((x) => Math.tan((Math.PI / 4) * ((2 * x) / n - 1)));
      const l = Math.hypot(...t);
      v = pos.length / 3;
      pos.push(...t.map((x) => (SPHERE_R * x) / l));
      index.set(key, v);
    }
    return v;
  };
  const tri = [];
  for (let ax = 0; ax < 3; ax++) {
    for (const side of [0, n]) {
      const [ua, va] = [(ax + 1) % 3, (ax + 2) % 3];
      for (let i = 0; i < n; i++) {
        for (let j = 0; j < n; j++) {
          const at = (di, dj) => { const c = [0, 0, 0]; c[ax] = side; c[ua] = i + di; c[va] = j + dj; return id(c); };
          const q = [at(0, 0), at(1, 0), at(1, 1), at(0, 1)];
          const pair = (i + j) % 2 === 0 ? [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] : [[q[0], q[1], q[3]], [q[1], q[2], q[3]]];
          for (const t of pair) tri.push(...(side === 0 ? [t[0], t[2], t[1]] : t));
        }
      }
    }
  }
  const positions = Float64Array.from(pos, Math.fround);
  let pole = 0;
  for (let v = 1; v < positions.length / 3; v++) if (positions[3 * v + 2] < positions[3 * pole + 2]) pole = v;
  const exact = (x, y, z) => SPHERE_R * Math.acos(Math.min(1, Math.max(-1, -z / Math.hypot(x, y, z))));
  return { positions, triangles: Uint32Array.from(tri), pole, exact };
}

const SHAPES = { cap, section, sphere };

function toBinaryStl({ positions: p, triangles: t }) {
  const count = t.length / 3;
  const bytes = new Uint8Array(84 + 50 * count);
  const view = new DataView(bytes.buffer);
  view.setUint32(80, count, true);
  let o = 84;
  for (let f = 0; f < count; f++) {
    o += 12;
    for (let k = 0; k < 3; k++) {
      for (let c = 0; c < 3; c++) { view.setFloat32(o, p[3 * t[3 * f + k] + c], true); o += 4; }
    }
    o += 2;
  }
  return bytes;
}

function errors(positions, distance, exact) {
  let [max, sum] = [0, 0];
  for (let v = 0; v < distance.length; v++) {
    const e = Math.abs(distance[v] - exact(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]));
    max = Math.max(max, e);
    sum += e;
  }
  return { maxError: max, meanError: sum / distance.length };
}

/** Child process: one method on one case, first after the page's warm-up when `page`. */
async function runCase(shape, target, method, page) {
  const { initSync, Mesh, reserveMemory } = await import(join(root, 'dist/pkg/skinpath.js'));
  initSync({ module: readFileSync(join(root, 'dist/pkg/skinpath_bg.wasm')) });
  const mesh3 = SHAPES[shape](target);
  const mesh = Mesh.fromStl(toBinaryStl(mesh3));
  // As in the page: the model is open, then the worker warms up while the user looks at it,
  // and the Paths tool, once opened, has the surface of a distance on the whole model
  // derived and the memory of its first distance reserved.
  if (page) {
    const { warmUp, reserveFirstDistance } = await import(join(root, 'dist/worker/warm-up.js'));
    warmUp(Mesh);
    mesh.prepareGeodesic();
    reserveFirstDistance(reserveMemory, mesh.triangleCount);
  }
  const positions = mesh.positions();
  let source = { boundaryOf: 'mesh' };
  if (shape === 'section') {
    const z = CAP_R * Math.cos(mesh3.theta);
    source = { plane: { point: [CAP_R * Math.sin(mesh3.theta), 0, z], normal: [0, 0, 1] } };
  }
  if (shape === 'sphere') {
    let pole = 0;
    for (let v = 1; v < positions.length / 3; v++) if (positions[3 * v + 2] < positions[3 * pole + 2]) pole = v;
    source = { vertices: [pole] };
  }
  let t = performance.now();
  const field = mesh.geodesicDistance(source, { method });
  const ms = performance.now() - t;
  const result = { shape, triangles: mesh3.triangles.length / 3, method: field.method, ms,
    ...errors(positions, field.vertexDistance(), mesh3.exact) };
  field.free();
  // The same call again: the engine's optimised code is ready and the memory grown.
  result.warm = NaN;
  if (method !== 'exact') {
    t = performance.now();
    mesh.geodesicDistance(source, { method }).free();
    result.warm = performance.now() - t;
  }
  mesh.free();
  return result;
}

const PYTHON_FMM = `
import sys, time, json, numpy as np, potpourri3d as pp3d
d = sys.argv[1]
V = np.fromfile(d + '/V.bin', dtype=np.float64).reshape(-1, 3)
F = np.fromfile(d + '/F.bin', dtype=np.int32).reshape(-1, 3)
src = [int(x) for x in np.fromfile(d + '/S.bin', dtype=np.int32)]
closed = sys.argv[2] == 'closed'
runs = int(sys.argv[3])
t0 = time.perf_counter()
solver = pp3d.MeshFastMarchingDistanceSolver(V, F)
t1 = time.perf_counter()
curve = [(v, []) for v in src] + ([(src[0], [])] if closed else [])
solves = []
for _ in range(runs):
    t2 = time.perf_counter()
    dist = np.asarray(solver.compute_distance([curve], [], False))
    solves.append(1000 * (time.perf_counter() - t2))
dist.astype(np.float64).tofile(d + '/D.bin')
print(json.dumps({'setup': 1000 * (t1 - t0), 'solves': solves}))
`;

/** The venv's python with potpourri3d 1.4.0, or a reason why there is none. */
function potpourri() {
  const python = join(VENV, 'bin', 'python');
  const ok = () => spawnSync(python, ['-c', 'import potpourri3d'], { stdio: 'ignore' }).status === 0;
  if (existsSync(python) && ok()) return { python };
  if (spawnSync('python3', ['--version'], { stdio: 'ignore' }).status !== 0) return { why: 'python3 is not available' };
  mkdirSync(dirname(VENV), { recursive: true });
  console.log(`(setting up potpourri3d 1.4.0 in a virtual environment: ${VENV})`);
  const venv = spawnSync('python3', ['-m', 'venv', VENV], { encoding: 'utf8' });
  if (venv.status !== 0) return { why: `python3 -m venv failed: ${(venv.stderr || '').trim().split('\n').pop()}` };
  const pip = spawnSync(join(VENV, 'bin', 'pip'), ['install', '--quiet', 'potpourri3d==1.4.0'], { encoding: 'utf8' });
  if (pip.status !== 0 || !ok()) return { why: `pip install potpourri3d==1.4.0 failed: ${(pip.stderr || '').trim().split('\n').pop()}` };
  return { python };
}

/** Fast marching on the same mesh and source: times and errors. */
function runFmm(python, shape, target) {
  const m = SHAPES[shape](target);
  const dir = mkdtempSync(join(tmpdir(), 'skinpath-fmm-'));
  try {
    writeFileSync(join(dir, 'V.bin'), new Uint8Array(m.positions.buffer));
    writeFileSync(join(dir, 'F.bin'), new Uint8Array(Int32Array.from(m.triangles).buffer));
    const src = shape === 'cap' ? m.rim : shape === 'section' ? m.ring : [m.pole];
    writeFileSync(join(dir, 'S.bin'), new Uint8Array(Int32Array.from(src).buffer));
    const out = execFileSync(python, ['-c', PYTHON_FMM, dir, shape === 'sphere' ? 'point' : 'closed', String(RUNS)],
      { encoding: 'utf8' });
    const { setup, solves } = JSON.parse(out.trim().split('\n').pop());
    const times = { setup, solve: median(solves) };
    const d = new Float64Array(readFileSync(join(dir, 'D.bin')).buffer.slice(0));
    return { ...times, ...errors(m.positions, d, m.exact) };
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

export async function main() {
  console.log('\ngeodesic distance on doubly curved meshes against the analytic distance:' +
    `\n  cap: R ${CAP_R} mm, half-angle 1 rad, rim as source, distance R·(1 − θ);` +
    '\n  section: the same cap, the source its section by the plane through its ring of vertices nearest to' +
    ' θ = 0.6 (fast marching: that ring as a closed curve), distance R·|θ − θs|;' +
    `\n  sphere: R ${SPHERE_R} mm (cube sphere), point source at the south pole, great-circle distance.` +
    '\n  Time: geodesicDistance alone (WebAssembly in Node); fast marching: potpourri3d 1.4.0, native, solve' +
    ' (and setup + solve); ×FMM: time / fast-marching solve time.' +
    `\n  Times: medians of ${RUNS} runs (GEODESIC_CURVED_RUNS), each of ours in a fresh process (cold: the first call there;` +
    ' page: the first call after the page\'s warm-up and what the Paths tool prepares when opened (the surface, the memory), www/worker/paths.js; warm: the same call again), fast marching\'s by one solver.');
  const fmm = potpourri();
  if (fmm.why) console.log(`  fast marching column left out: ${fmm.why}.`);
  console.log('shape    triangles  method          cold ms   ×FMM  page ms   ×FMM  warm ms   ×FMM   max err mm  mean err mm');
  for (const shape of ['cap', 'section', 'sphere']) {
    for (const size of SIZES) {
      let ref = null;
      if (fmm.python) {
        try {
          ref = runFmm(fmm.python, shape, size);
        } catch (e) {
          console.log(`  fast marching failed: ${e.message.split('\n')[0]}`);
        }
      }
      let triangles = size;
      for (const method of METHODS) {
        if (method === 'exact' && size > EXACT_MAX) {
          console.log(`${shape.padEnd(7)}${String(triangles).padStart(10)}  exact           skipped: minutes at this size (GEODESIC_EXACT_MAX=${EXACT_MAX})`);
          continue;
        }
        const runs = [];
        const pages = [];
        const child = (page) => JSON.parse(execFileSync(process.execPath,
          ['--max-old-space-size=8192', here, '--case', shape, String(size), method, page ? 'page' : 'cold'],
          { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] }));
        // `exact` once and cold: it is the reference for accuracy, not for speed.
        for (let k = 0; k < (method === 'exact' ? 1 : RUNS); k++) {
          runs.push(child(false));
          if (method !== 'exact') pages.push(child(true).ms);
        }
        const r = { ...runs[0], ms: median(runs.map((x) => x.ms)), warm: median(runs.map((x) => x.warm ?? NaN)),
          page: pages.length ? median(pages) : NaN };
        triangles = r.triangles;
        const ratio = (ms) => (ref && ms === ms ? (ms / ref.solve).toFixed(2) : '–').padStart(5);
        const time = (ms, width) => (ms === ms ? ms.toFixed(0) : '–').padStart(width);
        console.log(`${shape.padEnd(7)}${String(r.triangles).padStart(10)}  ${r.method.padEnd(12)}  ${time(r.ms, 7)}  ${ratio(r.ms)}` +
          `  ${time(r.page, 7)}  ${ratio(r.page)}  ${time(r.warm, 7)}  ${ratio(r.warm)}` +
          `  ${r.maxError.toExponential(2).padStart(11)}  ${r.meanError.toExponential(2).padStart(11)}`);
      }
      if (ref) {
        console.log(`${shape.padEnd(7)}${String(triangles).padStart(10)}  fast marching  ${ref.solve.toFixed(0).padStart(7)}` +
          `  ${'1.00'.padStart(5)}  ${''.padStart(7)}  ${''.padStart(5)}  ${''.padStart(7)}  ${''.padStart(5)}` +
          `  ${ref.maxError.toExponential(2).padStart(11)}  ${ref.meanError.toExponential(2).padStart(11)}` +
          `   (setup + solve ${(ref.setup + ref.solve).toFixed(0)} ms)`);
      }
    }
  }
}

const caseArg = process.argv.indexOf('--case');
if (process.argv[1] === here && caseArg > 0) {
  const [shape, size, method, mode] = process.argv.slice(caseArg + 1);
  process.stdout.write(JSON.stringify(await runCase(shape, Number(size), method, mode === 'page')));
} else if (process.argv[1] === here) {
  await main();
}
