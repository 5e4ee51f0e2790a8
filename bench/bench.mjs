// `npm run bench`: times the core on generated meshes and prints figures (asserts nothing).
// `npm run bench -- page` (also part of the whole run): a large file opened in the page in
// headless Chromium, stage by stage (see page.mjs).
//
// For each case, a child process (so every run starts from a fresh WebAssembly memory)
// generates a binary STL — a closed, fuselage-like surface of revolution at several sizes, and
// a box of integer-coordinate grids (structured bit patterns: the welding hash's stress
// case), a fan of triangles around one vertex (a disc tessellated from its centre, as CAD
// exports cap cylinders) and a "book" of triangles on one edge (the high-valence cases that
// once made the adjacency quadratic) and an aircraft-like file of several shells (fuselage,
// wings, tails, open nacelles; mixed windings, slivers; see aircraftStl) — then measures in one
// process:
//   - Mesh.fromStl (parse, weld, adjacency, winding, face geometry)
//   - mesh.segment with the paper's parameters (α 0.35 rad, θmax 1 rad, ε 10 %)
//   - three.js STLLoader.parse of the same bytes (a plain, unwelded parse) for comparison
//   - WebAssembly memory after import + segmentation, per triangle
// Times are medians of several runs after a warm-up (15 up to 1.5M triangles), each call
// started after a full garbage collection and a pause (see settle), the three interleaved so
// that load on a shared machine falls on all of them alike. `BENCH_STAGES=1 npm run bench` also
// prints the median time of each stage, from the progress reports (see stageTimes).
// Spray cases: a generated cylindrical skin panel, a plate, a real skin (the wing-body
// model's largest patch) and a whole-aircraft patch planned as the page plans it (the 747's
// largest patch with the page's sample budget), from the shared test models beside the
// project (skipped with a word when they are not there); Mesh.fromStl as the yardstick, one spacing search
// (maxError 0.2) on a fresh mesh, one planSpray (plan + simulate at one spacing) and the search again, both on
// the samples the mesh kept from the first, with the evaluation samples per second of the single plan. `npm run bench -- spray` runs only those.
// Geodesic cases: an open cylinder R 50 mm × 120 mm (the paper's model 2) with the bottom
// ring as source, where the exact distance is z, and a wavy height field z = A·sin(2πx/λ)
// extruded along y with the edge x = 0 as source, where it is the arc length of the profile;
// distance + iso-paths (spacing 10 mm) + tool path by the mesh, exact and voxel methods (voxel edge
// GEODESIC_VOXEL mm, default 0.25), with time, WebAssembly memory and the largest error of the
// path points against the analytic distance. `npm run bench -- geodesic` runs only those.
import { execFileSync } from 'node:child_process';
import { existsSync, readFileSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const CASES = [['fuselage', 20_000], ['fuselage', 200_000], ['fuselage', 1_000_000],
  ['fuselage', 2_000_000], ['fuselage', 4_000_000], ['grid', 1_000_000], ['fan', 80_000],
  ['fan', 1_000_000], ['book', 50_000], ['aircraft', 1_000_000], ['aircraft', 4_000_000]];
const SHAPES = ['fuselage', 'grid', 'fan', 'book', 'aircraft'];
// A number: the curved panel of about that many triangles; `plate`: the 119k-triangle plate of
// 2 mm triangles (0.49 m square) searched with maxError 0.10 on 30–250 mm.
const SPRAY_CASES = (process.env.SPRAY_CASES ?? "20000,100000,500000,plate,wingbody,b747").split(",");
/** The real skin of the spray cases: the largest patch of the wing-body model (a fuselage skin)
 *  under the paper's segmentation, from the shared test models beside the project. */
const WINGBODY = join(root, '..', 'shared', 'models', 'wingbody_79868_flow360.stl');
/** A whole-aircraft patch as the page plans it: the 747's largest patch under the same
 *  segmentation, with the page's budget of 100,000 evaluation samples (about 96 mm apart). */
const B747 = join(root, '..', 'shared', 'models', 'b747_14062_flightgear.stl');
const PAGE_SAMPLE_BUDGET = 100_000;
const GEODESIC_CASES = (process.env.GEODESIC_CASES ?? "cylinder:200000,cylinder:2000000,wave:500000")
  .split(",").map((c) => { const [shape, size] = c.split(":"); return [shape, Number(size)]; });
const GEODESIC_VOXEL = Number(process.env.GEODESIC_VOXEL ?? 0.25);

function toBinaryStl(tris) {
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

/** The six faces of an n × n × n box, each an integer grid: about `target` triangles. */
export function gridBoxStl(target) {
  const n = Math.max(1, Math.round(Math.sqrt(target / 12)));
  const tris = [];
  const faces = [
    (a, b) => [b, a, 0], (a, b) => [a, b, n], (a, b) => [a, 0, b],
    (a, b) => [b, n, a], (a, b) => [0, a, b], (a, b) => [n, b, a],
  ];
  for (const p of faces) {
    for (let i = 0; i < n; i++) {
      for (let j = 0; j < n; j++) {
        tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)], [p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
      }
    }
  }
  return toBinaryStl(tris);
}

/** `target` triangles around one vertex: a shallow cone over a disc (one vertex of valence
 * `target`, the rim open). */
export function fanStl(target) {
  const rim = (i) => {
    const a = (2 * Math.PI * (i % target)) / target;
    return [Math.cos(a), Math.sin(a), 0];
  };
  const tris = [];
  for (let i = 0; i < target; i++) tris.push([[0, 0, 0.2], rim(i), rim(i + 1)]);
  return toBinaryStl(tris);
}

/** `target` triangles sharing one edge (a non-manifold "book"), pages all around it. */
export function bookStl(target) {
  const tris = [];
  for (let i = 0; i < target; i++) {
    const a = (2 * Math.PI * i) / target;
    tris.push([[0, 0, 0], [0, 0, 1], [Math.cos(a), Math.sin(a), 0.5]]);
  }
  return toBinaryStl(tris);
}

/**
 * An aircraft-like file of about `target` triangles in several shells, as CAD exports them:
 * a closed fuselage (40 %), two closed tapered wings (15 % each, the left one written with
 * the opposite winding), a horizontal and a vertical tail (6 % each, closed), two open
 * engine nacelles (9 % each, open at both ends: boundary edges) and a little of what real
 * files carry: about 1 face in 200 of the wings written reversed (mixed windings inside a
 * shell), and 0.5 % slivers (needle triangles between existing corners, some below the
 * degeneracy ratio) along the fuselage. Deterministic (a fixed linear congruential seed).
 */
export function aircraftStl(target) {
  let seed = 0x2545f491;
  const random = () => ((seed = (Math.imul(seed, 1664525) + 1013904223) >>> 0) / 2 ** 32);
  const tris = [];
  // A grid of quads u ∈ [0, nu), v ∈ [0, nv] over `point(u, v)`, closed in u.
  const sheet = (count, point, { reverse = false, flipShare = 0, closeV = false } = {}) => {
    const nu = Math.max(8, Math.round(Math.sqrt(count / 2) * 1.6));
    const nv = Math.max(2, Math.round(count / (2 * nu)));
    for (let j = 0; j < nv; j++) {
      for (let i = 0; i < nu; i++) {
        const a = point(i % nu, j), b = point((i + 1) % nu, j), c = point((i + 1) % nu, j + 1), d = point(i % nu, j + 1);
        for (let t of [[a, b, c], [a, c, d]]) {
          if (reverse !== (random() < flipShare)) t = [t[0], t[2], t[1]];
          tris.push(t);
        }
      }
    }
    if (closeV) {
      // Caps: a fan from the centre of each end ring.
      for (const j of [0, nv]) {
        const ring = Array.from({ length: nu }, (_, i) => point(i, j));
        const centre = [0, 1, 2].map((k) => ring.reduce((s, p) => s + p[k], 0) / nu);
        for (let i = 0; i < nu; i++) {
          const t = j === 0 ? [centre, ring[(i + 1) % nu], ring[i]] : [centre, ring[i], ring[(i + 1) % nu]];
          tris.push(reverse ? [t[0], t[2], t[1]] : t);
        }
      }
    }
    return { nu, nv };
  };
  // Fuselage: 40 m long, radius 2.5 m, rounded nose and tapering tail (closed at both tips).
  const fuselage = Math.round(target * 0.4);
  {
    const around = Math.max(8, Math.round(Math.sqrt(fuselage)));
    const along = Math.max(4, Math.round(fuselage / (2 * around)));
    const point = (i, j) => {
      const t = j / along;
      const r = t === 0 || t === 1 ? 0 : 2.5 * Math.min(1, Math.sqrt(t / 0.12), Math.sqrt((1 - t) / 0.25));
      const a = (2 * Math.PI * (i % around)) / around;
      return [t * 40, r * Math.cos(a), r * Math.sin(a) + 0.3 * t];
    };
    for (let j = 0; j < along; j++) {
      for (let i = 0; i < around; i++) {
        const a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
        if (j > 0) tris.push([a, c, b]);
        if (j < along - 1) tris.push([a, d, c]);
        // Slivers: a needle from a corner to the middle of the opposite edge, nearly flat.
        if (j > 0 && j < along - 1 && random() < 0.005) {
          const m = [0, 1, 2].map((k) => 0.5 * (b[k] + c[k]) + (random() < 0.5 ? 1e-9 : 1e-6) * (a[k] - b[k]));
          tris.push([b, m, c]);
        }
      }
    }
  }
  // An airfoil-like closed section (NACA-style thickness 12 %) swept from `root` to `tip`.
  const wing = (count, rootX, rootChord, tipChord, span, sweep, dihedral, side, axis, options) => {
    const section = (u) => {
      const s = (2 * u) / nu; // 0..2 around the section
      const x = s <= 1 ? 1 - s : s - 1;
      const thickness = 0.6 * (0.2969 * Math.sqrt(x) - 0.126 * x - 0.3516 * x * x + 0.2843 * x ** 3 - 0.1036 * x ** 4);
      return [x, s <= 1 ? thickness : -thickness];
    };
    let nu = 0, nv = 0;
    const point = (i, j) => {
      const t = Math.min(j / nv, 1);
      const chord = rootChord + (tipChord - rootChord) * t;
      const [x, y] = section(i);
      const along = rootX + sweep * t + x * chord;
      const out = side * span * t;
      const up = y * chord + dihedral * t;
      return axis === 'y' ? [along, out + side * 2.4, up] : [along, y * chord, 2.4 + span * t];
    };
    // The grid size is decided before the points are needed.
    nu = Math.max(8, Math.round(Math.sqrt(count / 2) * 1.6));
    nv = Math.max(2, Math.round(count / (2 * nu)));
    sheet(count, point, { ...options, closeV: true });
  };
  wing(Math.round(target * 0.15), 14, 7, 2, 17, 6, 1.2, 1, 'y', { flipShare: 0.005 });
  wing(Math.round(target * 0.15), 14, 7, 2, 17, 6, 1.2, -1, 'y', { reverse: true, flipShare: 0.005 });
  wing(Math.round(target * 0.06), 35, 3, 1.2, 6, 2, 0.3, 1, 'y', {});
  wing(Math.round(target * 0.06), 34, 4, 2, 6, 3, 0, 1, 'z', {});
  // Nacelles: open tubes under the wings (their rims are boundary edges).
  for (const side of [1, -1]) {
    const count = Math.round(target * 0.09);
    const nu = Math.max(8, Math.round(Math.sqrt(count / 2) * 1.6));
    const nv = Math.max(2, Math.round(count / (2 * nu)));
    sheet(count, (i, j) => {
      const a = (2 * Math.PI * i) / nu;
      const r = 1.1 - 0.15 * Math.sin((Math.PI * j) / nv);
      return [12 + (4.5 * j) / nv, side * 7 + r * Math.cos(a), -1.6 + r * Math.sin(a)];
    });
  }
  return toBinaryStl(tris);
}

const GENERATORS = { fuselage: fuselageStl, grid: gridBoxStl, fan: fanStl, book: bookStl, aircraft: aircraftStl };

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
  return toBinaryStl(tris);
}

/** A cylindrical skin panel (radius 3, ±20°, length 2.5: about 2 × 2.5 in metres) of about
 *  `target` triangles, normals outwards. */
export function panelStl(target) {
  const length = 2.5, radius = 3, half = (20 * Math.PI) / 180;
  const across = Math.max(2, Math.round(Math.sqrt(target / 2 / (length / (2 * radius * half)))));
  const along = Math.max(2, Math.round(target / (2 * across)));
  const point = (i, j) => {
    const a = -half + (2 * half * j) / across;
    return [radius * Math.cos(a), radius * Math.sin(a), length * (1 - i / along)];
  };
  const tris = [];
  for (let j = 0; j < across; j++) {
    for (let i = 0; i < along; i++) {
      tris.push([point(i, j), point(i + 1, j), point(i + 1, j + 1)], [point(i, j), point(i + 1, j + 1), point(i, j + 1)]);
    }
  }
  return toBinaryStl(tris);
}

/** The page's spray defaults in metres: h 250 mm, v 400 mm/s, α 40°, Q 150 cm³/min, η 0.6, β_T 20°. */
const SPRAY = {
  spacing: 0.09, standoff: 0.25, speed: 0.4, flowRate: 150e-6 / 60, coneAngle: (40 * Math.PI) / 180,
  transitionAngle: (20 * Math.PI) / 180, efficiency: 0.6,
};

/** Flat square plate of `n` × `n` squares of `edge` m, two triangles each. */
function plateStl(n, edge) {
  const tris = [];
  const p = (i, j) => [i * edge, j * edge, 0];
  for (let j = 0; j < n; j++) {
    for (let i = 0; i < n; i++) tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)], [p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
  }
  return toBinaryStl(tris);
}

async function runSpray(name) {
  const model = { wingbody: WINGBODY, b747: B747 }[name];
  if (model && !existsSync(model)) return { name, skipped: 'the shared test models (../shared/models) are not beside the project' };
  const { initSync, Mesh } = await import(join(root, 'dist/pkg/skinpath.js'));
  initSync({ module: readFileSync(join(root, 'dist/pkg/skinpath_bg.wasm')) });
  const plate = name === 'plate';
  const real = Boolean(model);
  const bytes = real ? readFileSync(model) : plate ? plateStl(244, 0.002) : panelStl(Number(name));
  const quality = plate ? { maxError: 0.1, minSpacing: 0.03, maxSpacing: 0.25 } : { maxError: 0.2 };
  const spray = name === 'b747' ? { ...SPRAY, sampleBudget: PAGE_SAMPLE_BUDGET } : SPRAY;
  // The real skin: the paper's segmentation (α 0.35 rad, θmax 1 rad, 10 % area), its largest
  // patch; segmentation is not timed.
  const patchOf = (mesh) => {
    if (!real) return undefined;
    const seg = mesh.segment({ angleThreshold: 0.35, thetaMax: 1.0, minAreaRatio: 0.1 });
    const faces = seg.patchFaces(0);
    seg.free();
    return faces;
  };
  const triangles = (bytes.length - 84) / 50;
  // The yardstick is timed twice a run, once on each side of the search, so both see the
  // same load on a shared machine.
  const runs = triangles > 300_000 ? 1 : 5;
  const parse = [], plan = [], search = [], warm = [];
  let samples = 0, passes = 0, found = 0, tried = 0, patchFaces = 0, cycle = 0;
  for (let r = 0; r < runs; r++) {
    await settle();
    let t = performance.now();
    const mesh = Mesh.fromStl(bytes);
    parse.push(performance.now() - t);
    const faces = patchOf(mesh);
    patchFaces = faces ? faces.length : triangles;
    // The search on a mesh that has planned nothing yet (cold), then a plan and the search
    // again on the samples the mesh keeps (as the page re-plans after a change of spacing,
    // speed, limits or direction): the same results.
    t = performance.now();
    const best = mesh.planSpray({ ...spray, quality }, faces);
    search.push(performance.now() - t);
    passes = best.passCount; found = best.spacing; tried = best.iterations().length; cycle = best.cycleTime;
    best.free();
    t = performance.now();
    const one = mesh.planSpray(spray, faces);
    plan.push(performance.now() - t);
    samples = one.sampleThickness().length;
    one.free();
    t = performance.now();
    mesh.planSpray({ ...spray, quality }, faces).free();
    warm.push(performance.now() - t);
    mesh.free();
    t = performance.now();
    Mesh.fromStl(bytes).free();
    parse.push(performance.now() - t);
  }
  const [p, q, s, w] = [median(parse), median(plan), median(search), median(warm)];
  return { name, triangles: real ? `${patchFaces}/${triangles}` : triangles, fromStl: p, plan: q, search: s, ratio: s / p, warm: w, warmRatio: w / p,
    samples, samplesPerSecond: samples / (q / 1000),
    passes, spacing: found, tried, cycle };
}

/** Open cylinder about z, radius 50, z in [0, 120], about `target` triangles of even shape;
 *  the source is its bottom ring through the vertices, the exact distance is z. */
function geodesicCylinder(target) {
  const [r, h] = [50, 120];
  const n = Math.max(8, Math.round(Math.sqrt((target / 2) * (2 * Math.PI * r) / h)));
  const m = Math.max(1, Math.round(target / (2 * n)));
  const p = (i, j) => {
    const a = (2 * Math.PI * (i % n)) / n;
    return [r * Math.cos(a), r * Math.sin(a), (h * j) / m];
  };
  const tris = [];
  for (let j = 0; j < m; j++) {
    for (let i = 0; i < n; i++) tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)], [p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
  }
  const ring = new Float64Array(3 * n);
  for (let i = 0; i < n; i++) ring.set(p(i, 0).map(Math.fround), 3 * i);
  return { bytes: toBinaryStl(tris), source: { polyline: ring, closed: true }, exact: (x, y, z) => z };
}

/** Height field z = 8·sin(2πx/40) over 60 × 50 mm (the paper's model 3 size), about `target`
 *  triangles; the source is the edge x = 0, the exact distance the profile's arc length. */
function geodesicWave(target) {
  const [w, d, a, lambda] = [60, 50, 8, 40];
  const n = Math.max(2, Math.round(Math.sqrt((target / 2) * (w / d))));
  const m = Math.max(1, Math.round(target / (2 * n)));
  const z = (x) => a * Math.sin((2 * Math.PI * x) / lambda);
  const p = (i, j) => [(w * i) / n, (d * j) / m, z((w * i) / n)];
  const tris = [];
  for (let j = 0; j < m; j++) {
    for (let i = 0; i < n; i++) tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)], [p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
  }
  // Arc length s(x) tabulated by the midpoint rule on 200 000 steps (error far below 1e-6 mm).
  const steps = 200_000;
  const table = new Float64Array(steps + 1);
  const slope = (x) => ((a * 2 * Math.PI) / lambda) * Math.cos((2 * Math.PI * x) / lambda);
  for (let k = 0; k < steps; k++) table[k + 1] = table[k] + Math.hypot(1, slope(((k + 0.5) * w) / steps)) * (w / steps);
  const exact = (x) => {
    const t = Math.min(Math.max((x / w) * steps, 0), steps);
    const k = Math.min(Math.floor(t), steps - 1);
    return table[k] + (t - k) * (table[k + 1] - table[k]);
  };
  return { bytes: toBinaryStl(tris), source: { polyline: [0, 0, 0, 0, d, 0] }, exact: (x) => exact(x) };
}

async function runGeodesic(shape, target, method) {
  const { initSync, Mesh, wasmMemoryBytes } = await import(join(root, 'dist/pkg/skinpath.js'));
  initSync({ module: readFileSync(join(root, 'dist/pkg/skinpath_bg.wasm')) });
  const { bytes, source, exact } = (shape === 'wave' ? geodesicWave : geodesicCylinder)(target);
  const triangles = (bytes.length - 84) / 50;
  const spacing = 10;
  let t = performance.now();
  const mesh = Mesh.fromStl(bytes);
  const fromStl = performance.now() - t;
  const params = method === 'voxel' ? { method, voxelSize: GEODESIC_VOXEL } : { method };
  t = performance.now();
  let field;
  try {
    field = mesh.geodesicDistance(source, params);
  } catch (e) {
    return { shape, triangles, method, error: e.message };
  }
  const distance = performance.now() - t;
  t = performance.now();
  const paths = field.isoPaths(spacing);
  const iso = performance.now() - t;
  t = performance.now();
  const path = field.toolPath(spacing);
  const toolPath = performance.now() - t;
  let worst = 0, sum = 0, count = 0;
  for (const p of paths) {
    for (let i = 0; i < p.points.length; i += 3) {
      const e = Math.abs(exact(p.points[i], p.points[i + 1], p.points[i + 2]) - p.distance);
      worst = Math.max(worst, e); sum += e; count++;
    }
  }
  const result = { shape, triangles, method, fromStl, distance, iso, toolPath, paths: paths.length,
    closed: paths.filter((p) => p.closed).length, points: count, maxError: worst, meanError: sum / count,
    voxels: field.voxelCount, voxelMiB: field.voxelMemoryBytes / 2 ** 20, memoryMiB: wasmMemoryBytes() / 2 ** 20,
    poses: path.poseCount };
  path.free(); field.free(); mesh.free();
  return result;
}

/**
 * A full garbage collection, then a pause for the collector's background threads (sweeping,
 * returning pages) to finish, so that neither timed call shares the machine with them.
 */
async function settle() {
  globalThis.gc?.();
  await new Promise((resolve) => setTimeout(resolve, 50));
}

function median(xs) {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

async function runOne(shape, target) {
  const { initSync, Mesh, wasmMemoryBytes } = await import(join(root, 'dist/pkg/skinpath.js'));
  const { STLLoader } = await import('three/examples/jsm/loaders/STLLoader.js');
  initSync({ module: readFileSync(join(root, 'dist/pkg/skinpath_bg.wasm')) });
  const bytes = GENERATORS[shape](target);
  const triangles = (bytes.length - 84) / 50;
  const params = { angleThreshold: 0.35, thetaMax: 1, minAreaRatio: 0.1 };
  const runs = triangles > 3_000_000 ? 3 : triangles > 1_500_000 ? 5 : 15;

  // First run: memory of one import + segmentation from a fresh module.
  let mesh = Mesh.fromStl(bytes);
  let seg = mesh.segment(params);
  const memory = wasmMemoryBytes();
  const patches = seg.patchCount;
  seg.free(); mesh.free();

  const parse = [], segment = [], three = [];
  const loader = new STLLoader();
  for (let r = 0; r < runs; r++) {
    await settle();
    let t = performance.now();
    const g = loader.parse(bytes.buffer);
    three.push(performance.now() - t);
    g.dispose();
    await settle();
    t = performance.now();
    mesh = Mesh.fromStl(bytes);
    parse.push(performance.now() - t);
    t = performance.now();
    seg = mesh.segment(params);
    segment.push(performance.now() - t);
    seg.free(); mesh.free();
  }
  const [p, s, l] = [median(parse), median(segment), median(three)];
  const stages = process.env.BENCH_STAGES ? await stageTimes(Mesh, bytes, params, runs) : undefined;
  return { shape, triangles, fromStl: p, segment: s, stlLoader: l, ratio: (p + s) / l,
    bytesPerTriangle: memory / triangles, memoryMiB: memory / 2 ** 20, patches, stages };
}

/**
 * Medians over `runs` runs of the time between the stage changes the core reports through
 * onProgress (`BENCH_STAGES=1 npm run bench`): copy-in (of the file's head: a binary file is
 * streamed into the engine as it is parsed), parse (read + weld), adjacency, orient,
 * geometry; regions, seeds (seed order: from the first `planarise` report at 0 to the next
 * one), planarise, patches. The first report of a stage ends the one before.
 */
async function stageTimes(Mesh, bytes, params, runs) {
  const all = {};
  for (let r = 0; r < runs; r++) {
    await settle();
    const marks = [];
    let last;
    const onProgress = (stage, fraction) => {
      const name = stage === 'planarise' && fraction === 0 && last === 'planarise' ? 'planarise*' : stage;
      if (name !== last || name === 'planarise*') marks.push([name, performance.now()]);
      last = stage;
    };
    const start = performance.now();
    const mesh = Mesh.fromStl(bytes, onProgress);
    marks.push(['end', performance.now()]);
    const seg = mesh.segment(params, onProgress);
    marks.push(['end', performance.now()]);
    seg.free(); mesh.free();
    marks.unshift(['start', start]);
    for (let i = 0; i < marks.length - 1; i++) {
      if (marks[i][0] === 'end') continue;
      let name = marks[i][0];
      // From the first `planarise` report to the second is the seed order.
      if (name === 'planarise' && marks[i + 1][0] === 'planarise*') name = 'seeds';
      if (name === 'planarise*') name = 'planarise';
      (all[name] ??= []).push(marks[i + 1][1] - marks[i][1]);
    }
  }
  // `start` is the copy of the bytes into WebAssembly memory before the first report: the
  // file's head, or the whole of a file read as text.
  return Object.fromEntries(Object.entries(all).map(([k, v]) => [k === 'start' ? 'copy-in' : k, median(v)]));
}

const isMain = process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1];
const sizeArg = !isMain ? -1 : process.argv.indexOf('--size');
const sprayArg = !isMain ? -1 : process.argv.indexOf('--spray');
const geodesicArg = !isMain ? -1 : process.argv.indexOf('--geodesic');
if (geodesicArg > 0) {
  const [shape, size, method] = process.argv.slice(geodesicArg + 1);
  process.stdout.write(JSON.stringify(await runGeodesic(shape, Number(size), method)));
} else if (sprayArg > 0) {
  process.stdout.write(JSON.stringify(await runSpray(process.argv[sprayArg + 1])));
} else if (sizeArg > 0) {
  const result = await runOne(process.argv[sizeArg + 2] ?? 'fuselage', Number(process.argv[sizeArg + 1]));
  process.stdout.write(JSON.stringify(result));
} else if (isMain) {
  // `npm run bench -- 50000 fuselage 300000 grid 80000 fan` runs only those cases (shapes:
  // fuselage, grid, fan, book, aircraft).
  const args = process.argv.slice(2);
  const chosen = [];
  for (let i = 0; i < args.length; i++) {
    const shape = SHAPES.includes(args[i + 1]) ? args[i + 1] : 'fuselage';
    if (Number(args[i])) chosen.push([shape, Number(args[i])]);
    if (shape === args[i + 1]) i++;
  }
  console.log('skinpath benchmark (Node %s): generated meshes, binary STL', process.version);
  const only = args.includes('spray') || args.includes('geodesic') || args.includes('page');
  const meshCases = chosen.length ? chosen : only ? [] : CASES;
  if (meshCases.length) {
    console.log('shape      triangles   fromStl ms  fromStl µs/tri  segment ms  STLLoader ms  (fromStl+segment)/STLLoader  wasm MiB  bytes/triangle  patches');
  }
  for (const [shape, size] of meshCases) {
    const out = execFileSync(process.execPath, ['--expose-gc', '--max-old-space-size=8192',
      fileURLToPath(import.meta.url), '--size', String(size), shape], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
    const r = JSON.parse(out);
    console.log(
      `${r.shape.padEnd(9)}${String(r.triangles).padStart(9)}  ${r.fromStl.toFixed(1).padStart(10)}` +
      `  ${(1000 * r.fromStl / r.triangles).toFixed(3).padStart(14)}  ${r.segment.toFixed(1).padStart(10)}` +
      `  ${r.stlLoader.toFixed(1).padStart(12)}  ${r.ratio.toFixed(2).padStart(27)}` +
      `  ${r.memoryMiB.toFixed(1).padStart(8)}  ${r.bytesPerTriangle.toFixed(1).padStart(14)}  ${String(r.patches).padStart(7)}`);
    if (r.stages) {
      console.log(`           stages ms: ${Object.entries(r.stages).map(([k, v]) => `${k} ${v.toFixed(1)}`).join(', ')}`);
    }
  }
  if ((!chosen.length && !only) || args.includes('spray')) {
    console.log('\nspray on a curved panel (2 × 2.5 m, page defaults; search with maxError 0.2), on a plate of 2 mm triangles (0.49 m square; maxError 0.10 on 30–250 mm)' +
      ' and on a real skin (the wing-body model\'s largest patch, a fuselage skin: patch/model triangles; page defaults, maxError 0.2; fromStl of the whole model)' +
      `; 747: the 747's largest patch with the page's sampleBudget of ${PAGE_SAMPLE_BUDGET}`);
    console.log('search: the first on the mesh; warm: again, on the samples the mesh keeps (as after a change of spacing, speed, limits or direction); plan: one spacing, on kept samples');
    console.log('      triangles   fromStl ms   plan ms   search ms  search/fromStl  warm ms  warm/fromStl  eval samples  samples/s (plan)  passes  spacing m  cycle s  tried');
    for (const size of SPRAY_CASES) {
      const out = execFileSync(process.execPath, ['--expose-gc', '--max-old-space-size=8192',
        fileURLToPath(import.meta.url), '--spray', String(size)], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
      const r = JSON.parse(out);
      if (r.skipped) {
        console.log(`${r.name.padEnd(15)}  skipped: ${r.skipped}`);
        continue;
      }
      const label = { plate: 'plate', wingbody: 'skin', b747: '747' }[r.name] ?? 'panel';
      // The triangle count (patch/model for the skin) right-aligned in 15 columns.
      console.log(`${label.padEnd(15 - String(r.triangles).length)}${r.triangles}  ${r.fromStl.toFixed(1).padStart(11)}  ${r.plan.toFixed(1).padStart(8)}` +
        `  ${r.search.toFixed(1).padStart(10)}  ${r.ratio.toFixed(1).padStart(14)}  ${r.warm.toFixed(1).padStart(7)}  ${r.warmRatio.toFixed(1).padStart(12)}  ${String(r.samples).padStart(12)}` +
        `  ${r.samplesPerSecond.toFixed(0).padStart(16)}  ${String(r.passes).padStart(6)}  ${r.spacing.toFixed(4).padStart(9)}  ${r.cycle.toFixed(1).padStart(7)}` +
        `  ${String(r.tried).padStart(5)}`);
    }
  }
  if ((!chosen.length && !only) || args.includes('geodesic')) {
    console.log(`\ngeodesic passes (spacing 10 mm; voxel edge ${GEODESIC_VOXEL} mm): cylinder R 50 × 120 mm from the bottom ring` +
      ' (exact: z), wave z = 8 sin(2πx/40) 60 × 50 mm from x = 0 (exact: arc length)');
    console.log('shape     triangles  method  distance ms  isoPaths ms  toolPath ms  paths  closed  max err mm  mean err mm     voxels  voxel MiB  wasm MiB');
    for (const [shape, size] of GEODESIC_CASES) {
      for (const method of ['accurate', 'fast', 'exact', 'voxel']) {
        const out = execFileSync(process.execPath, ['--expose-gc', '--max-old-space-size=8192',
          fileURLToPath(import.meta.url), '--geodesic', shape, String(size), method], { encoding: 'utf8', stdio: ['ignore', 'pipe', 'inherit'] });
        const r = JSON.parse(out);
        if (r.error) {
          console.log(`${r.shape.padEnd(9)}${String(r.triangles).padStart(10)}  ${r.method.padEnd(6)}  refused: ${r.error}`);
          continue;
        }
        console.log(`${r.shape.padEnd(9)}${String(r.triangles).padStart(10)}  ${r.method.padEnd(6)}  ${r.distance.toFixed(0).padStart(11)}` +
          `  ${r.iso.toFixed(0).padStart(11)}  ${r.toolPath.toFixed(0).padStart(11)}  ${String(r.paths).padStart(5)}  ${String(r.closed).padStart(6)}` +
          `  ${r.maxError.toExponential(2).padStart(10)}  ${r.meanError.toExponential(2).padStart(11)}  ${String(r.voxels).padStart(9)}` +
          `  ${r.voxelMiB.toFixed(1).padStart(9)}  ${r.memoryMiB.toFixed(1).padStart(8)}`);
      }
    }
    if (args.includes('geodesic')) await (await import('./geodesic.mjs')).main();
  }
  if ((!chosen.length && !only) || args.includes('page')) await (await import('./page.mjs')).main({ aircraftStl });
}
