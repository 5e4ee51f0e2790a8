// Mesh.geodesicDistance from the built wasm package in Node: every source form, the methods,
// iso-path heights on a cylinder against the analytic distance (a ring source at the bottom:
// distance = z), the ToolPath exports, the TypeScript names, and errors naming bad input.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const pkg = join(root, 'dist', 'pkg');
const wasm = await import(join(pkg, 'skinpath.js'));
wasm.initSync({ module: readFileSync(join(pkg, 'skinpath_bg.wasm')) });
const { Mesh, DistanceField, ToolPath } = wasm;

/** Binary STL of an open cylinder about z: radius r, z from 0 to h, n facets round, m rings. */
function cylinderStl(r, h, n, m) {
  const bytes = new Uint8Array(84 + 50 * 2 * n * m);
  const view = new DataView(bytes.buffer);
  view.setUint32(80, 2 * n * m, true);
  const p = (i, j) => {
    const a = (2 * Math.PI * (i % n)) / n;
    return [r * Math.cos(a), r * Math.sin(a), (h * j) / m];
  };
  let k = 0;
  const put = (t) => {
    t.flat().forEach((c, q) => view.setFloat32(84 + 50 * k + 12 + 4 * q, c, true));
    k++;
  };
  for (let j = 0; j < m; j++) {
    for (let i = 0; i < n; i++) {
      put([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
      put([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
    }
  }
  return bytes;
}

// The paper's model 2: R 50 mm, length 120 mm; 48 facets round, 24 rings (5 mm).
const N = 48;
const R = 50;
const mesh = Mesh.fromStl(cylinderStl(R, 120, N, 24));
const ring = new Float64Array(Array.from({ length: N }, (_, i) => {
  const a = (2 * Math.PI * i) / N;
  return [Math.fround(R * Math.cos(a)), Math.fround(R * Math.sin(a)), 0];
}).flat());
const ringSource = { polyline: ring, closed: true };

/** Largest |z − level·spacing| over every point of every path. */
function heightError(paths, spacing, offset = 0) {
  let worst = 0;
  for (const p of paths) {
    for (let i = 2; i < p.points.length; i += 3) {
      worst = Math.max(worst, Math.abs(Math.abs(p.points[i] - offset) - p.level * spacing));
    }
  }
  return worst;
}

function refuses(f, pattern) {
  assert.throws(f, (e) => {
    assert.ok(e instanceof Error, `an Error, got ${e}`);
    assert.match(e.message, pattern);
    return true;
  });
}

function stillWorks() {
  assert.equal(mesh.triangleCount, 2 * N * 24);
  const f = mesh.geodesicDistance(ringSource);
  assert.ok(Math.abs(f.maxDistance - 120) < 1e-3);
  f.free();
}

test('a ring source gives closed paths at z = 10k (fast method: error < 1e-6 mm)', () => {
  const stages = new Set();
  const field = mesh.geodesicDistance(ringSource, { method: 'fast' }, (stage, fraction) => {
    assert.ok(fraction >= 0 && fraction <= 1);
    stages.add(stage);
  });
  assert.ok(field instanceof DistanceField);
  assert.equal(field.method, 'fast');
  assert.ok(Math.abs(field.maxDistance - 120) < 1e-6);
  const d = field.vertexDistance();
  assert.equal(d.length, mesh.vertexCount);
  const pos = mesh.positions();
  for (let v = 0; v < d.length; v++) assert.ok(Math.abs(d[v] - pos[3 * v + 2]) < 1e-4, `vertex ${v}`);
  assert.equal(field.voxelCenters().length, 0);
  assert.equal(field.voxelDistance().length, 0);
  const paths = field.isoPaths(10);
  const levels = [...new Set(paths.map((p) => p.level))];
  assert.deepEqual(levels.slice(0, 11), [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11]);
  for (const p of paths) {
    assert.equal(p.closed, true);
    assert.equal(p.distance, 10 * p.level);
    assert.ok(p.points instanceof Float64Array && p.normals instanceof Float64Array);
    assert.equal(p.points.length, p.normals.length);
    // Normals are unit and horizontal (radial) on the cylinder.
    for (let i = 0; i < p.normals.length; i += 3) {
      assert.ok(Math.abs(Math.hypot(p.normals[i], p.normals[i + 1], p.normals[i + 2]) - 1) < 1e-9);
      assert.ok(Math.abs(p.normals[i + 2]) < 1e-6);
    }
  }
  assert.ok(heightError(paths, 10) < 1e-6, `height error ${heightError(paths, 10)}`);
  assert.ok(stages.size >= 1, 'progress was reported');
  field.free();
});

test('the accurate method is the default, and "mesh" still runs the fast method', () => {
  const stages = new Set();
  const field = mesh.geodesicDistance(ringSource, undefined, (stage, fraction) => {
    assert.ok(fraction >= 0 && fraction <= 1);
    stages.add(stage);
  });
  assert.equal(field.method, 'accurate');
  assert.ok(stages.size >= 1, 'progress was reported');
  const d = field.vertexDistance();
  const pos = mesh.positions();
  for (let v = 0; v < d.length; v++) assert.ok(Math.abs(d[v] - pos[3 * v + 2]) < 1e-4, `vertex ${v}`);
  assert.ok(heightError(field.isoPaths(10), 10) < 1e-6);
  field.free();
  const named = mesh.geodesicDistance(ringSource, { method: 'accurate' });
  assert.equal(named.method, 'accurate');
  named.free();
  const alias = mesh.geodesicDistance(ringSource, { method: 'mesh' });
  assert.equal(alias.method, 'fast');
  alias.free();
});

test('the exact method gives the distance z to rounding, and its circles', () => {
  const field = mesh.geodesicDistance(ringSource, { method: 'exact' });
  assert.equal(field.method, 'exact');
  const d = field.vertexDistance();
  const pos = mesh.positions();
  for (let v = 0; v < d.length; v++) assert.ok(Math.abs(d[v] - pos[3 * v + 2]) < 1e-9, `vertex ${v}`);
  // Level 12 runs along the top boundary itself (z = 120): left out.
  const paths = field.isoPaths(10).filter((p) => p.level <= 11);
  assert.deepEqual(paths.map((p) => p.level), [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11]);
  assert.ok(paths.every((p) => p.closed));
  assert.ok(heightError(paths, 10) < 1e-9, `height error ${heightError(paths, 10)}`);
  field.free();
});

test('on a small surface with corners the accurate method answers with the exact distance, and says so', () => {
  // A closed cube of side 40 mm, two triangles a face: from one corner, the far corner is
  // √5·40 mm away (the diagonal of two faces unfolded into a 40 × 80 rectangle).
  const s = 40;
  const c = (i) => [(i & 1) * s, ((i >> 1) & 1) * s, ((i >> 2) & 1) * s];
  const quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
  const bytes = new Uint8Array(84 + 50 * 12);
  const view = new DataView(bytes.buffer);
  view.setUint32(80, 12, true);
  let k = 0;
  for (const [a, b, d, e] of quads) {
    for (const t of [[a, b, d], [a, d, e]]) {
      t.flatMap(c).forEach((x, q) => view.setFloat32(84 + 50 * k + 12 + 4 * q, x, true));
      k++;
    }
  }
  const cube = Mesh.fromStl(bytes);
  const pos = cube.positions();
  const at = (x, y, z) => [...Array(pos.length / 3).keys()].find((v) => pos[3 * v] === x && pos[3 * v + 1] === y && pos[3 * v + 2] === z);
  const field = cube.geodesicDistance({ vertices: [at(0, 0, 0)] });
  assert.equal(field.method, 'exact');
  assert.ok(Math.abs(field.vertexDistance()[at(s, s, s)] - Math.sqrt(5) * s) < 1e-9);
  field.free();
  // The fast method is not switched.
  const fast = cube.geodesicDistance({ vertices: [at(0, 0, 0)] }, { method: 'fast' });
  assert.equal(fast.method, 'fast');
  fast.free();
  cube.free();
});

test("the page's warm-up takes the accurate method's own way on its cap and sphere", async () => {
  // The worker's warm-up (www/worker/warm-up.js) must make the code of a real panel's distance
  // hot: virtual sources from a curve and from a point, with focal points; not the exact
  // method, which the accurate one runs instead on small surfaces with corners.
  const { capStl, warmUp } = await import(join(root, 'dist', 'worker', 'warm-up.js'));
  const cap = Mesh.fromStl(capStl(24, 64, 1, 1000));
  const sphere = Mesh.fromStl(capStl(32, 64, Math.PI, 100));
  try {
    assert.equal(cap.report().boundaryEdges, 64);
    assert.equal(sphere.report().boundaryEdges, 0);
    assert.equal(sphere.report().components, 1);
    const rim = cap.geodesicDistance({ boundaryOf: 'mesh' }, { method: 'accurate' });
    assert.equal(rim.method, 'accurate');
    // The pole is R·θ0 from the rim, less the sag of the 64-gon rim (1.0 mm).
    assert.ok(Math.abs(rim.vertexDistance()[0] - 999) < 1, `pole ${rim.vertexDistance()[0]}`);
    rim.free();
    const z = sphere.positions();
    let south = 0;
    for (let v = 1; 3 * v < z.length; v++) if (z[3 * v + 2] < z[3 * south + 2]) south = v;
    const point = sphere.geodesicDistance({ vertices: [south] }, { method: 'accurate' });
    assert.equal(point.method, 'accurate');
    // The north pole (vertex 0, the focal point) is half a great circle away: π·R.
    assert.ok(Math.abs(point.vertexDistance()[0] - 100 * Math.PI) < 0.5, `antipode ${point.vertexDistance()[0]}`);
    point.free();
    const ms = warmUp(Mesh);
    assert.ok(ms > 0 && Number.isFinite(ms));
  } finally {
    cap.free();
    sphere.free();
  }
});

test('the voxel method finds the same circles within two voxels', () => {
  const L = 1;
  const field = mesh.geodesicDistance(ringSource, { method: 'voxel', voxelSize: L });
  assert.equal(field.method, 'voxel');
  assert.ok(field.voxelCount > 10000);
  assert.ok(field.voxelMemoryBytes > 0);
  assert.equal(field.voxelCenters().length, 3 * field.voxelCount);
  assert.equal(field.voxelDistance().length, field.voxelCount);
  assert.equal(field.vertexDistance().length, mesh.vertexCount);
  assert.ok(Math.abs(field.maxDistance - 120) < 2 * L, `max ${field.maxDistance}`);
  const paths = field.isoPaths(10, { maxLevel: 10 });
  assert.ok(paths.length >= 10);
  assert.deepEqual([...new Set(paths.map((p) => p.level))], [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]);
  assert.ok(heightError(paths, 10) < 2 * L, `height error ${heightError(paths, 10)}`);
  field.free();
});

test('vertices, boundary loops, patches and plane sections as sources', () => {
  const pos = mesh.positions();
  const bottom = [];
  for (let v = 0; v < mesh.vertexCount; v++) if (pos[3 * v + 2] === 0) bottom.push(v);
  assert.equal(bottom.length, N);
  const byVertices = mesh.geodesicDistance({ vertices: new Uint32Array(bottom) });
  assert.ok(Math.abs(byVertices.maxDistance - 120) < 1, `${byVertices.maxDistance}`);
  byVertices.free();
  const byArray = mesh.geodesicDistance({ vertices: bottom });
  assert.ok(byArray.maxDistance > 119);
  byArray.free();

  // Two loops of equal length: each one alone gives 120, both give 60 (the middle).
  const loop0 = mesh.geodesicDistance({ boundaryOf: 'mesh', loop: 0 });
  assert.ok(Math.abs(loop0.maxDistance - 120) < 1e-6);
  loop0.free();
  const both = mesh.geodesicDistance({ boundaryOf: 'mesh' });
  assert.ok(Math.abs(both.maxDistance - 60) < 1e-6);
  both.free();

  // The lower half as a patch: its loops are z = 0 and z = 60, distance ≤ 30.
  const idx = mesh.indices();
  const lower = [];
  for (let f = 0; f < mesh.triangleCount; f++) {
    const zs = [0, 1, 2].map((k) => pos[3 * idx[3 * f + k] + 2]);
    if (Math.max(...zs) <= 60) lower.push(f);
  }
  const patch = mesh.geodesicDistance({ boundaryOf: 3 }, { faces: new Uint32Array(lower) });
  assert.ok(Math.abs(patch.maxDistance - 30) < 1e-6, `${patch.maxDistance}`);
  const d = patch.vertexDistance();
  for (let v = 0; v < d.length; v++) {
    if (pos[3 * v + 2] > 60) assert.equal(d[v], Infinity, 'outside the patch');
  }
  patch.free();

  // The section z = 30: distance |z − 30|, paths on both sides.
  const plane = mesh.geodesicDistance({ plane: { point: [R, 0, 30], normal: [0, 0, 1] } });
  assert.ok(Math.abs(plane.maxDistance - 90) < 1e-6);
  const paths = plane.isoPaths(10, { maxLevel: 2 });
  assert.equal(paths.length, 4, 'two circles each side');
  assert.ok(heightError(paths, 10, 30) < 1e-6);
  plane.free();

  // A generator line: open lines on both sides at arc distance 10k (the facets' chords).
  const line = mesh.geodesicDistance({ polyline: [R, 0, 0, R, 0, 120] });
  const open = line.isoPaths(10, { maxLevel: 3 });
  assert.equal(open.length, 6);
  assert.ok(open.every((p) => !p.closed));
  line.free();
});

test('prepareGeodesic keeps what a distance derives from the mesh: the same distances and passes after it', () => {
  // A fresh mesh of the same file for the distances without anything kept.
  const fresh = Mesh.fromStl(cylinderStl(R, 120, N, 24));
  const kept = Mesh.fromStl(cylinderStl(R, 120, N, 24));
  const idx = kept.indices();
  const pos = kept.positions();
  const lower = [];
  for (let f = 0; f < kept.triangleCount; f++) {
    if (Math.max(...[0, 1, 2].map((k) => pos[3 * idx[3 * f + k] + 2])) <= 60) lower.push(f);
  }
  try {
    assert.equal(kept.prepareGeodesic(), undefined);
    const cases = [
      [{ boundaryOf: 'mesh' }, {}],
      [{ plane: { point: [R, 0, 30], normal: [0, 0, 1] } }, { method: 'fast' }],
      [{ boundaryOf: 3 }, { faces: lower }],
      [{ vertices: [0] }, {}],
    ];
    for (const [source, params] of [...cases, ...cases]) {
      const [a, b] = [fresh, kept].map((m) => m.geodesicDistance(source, params));
      assert.deepEqual(b.vertexDistance(), a.vertexDistance(), JSON.stringify(source));
      assert.deepEqual(b.isoPaths(10).map((p) => [...p.points]), a.isoPaths(10).map((p) => [...p.points]));
      a.free();
      b.free();
    }
    kept.prepareGeodesic({ faces: new Uint32Array(lower) });
    refuses(() => kept.prepareGeodesic({ faces: [kept.triangleCount] }), /face \d+ does not exist/);
    refuses(() => kept.prepareGeodesic({ faces: [] }), /faces is empty/);
    refuses(() => kept.prepareGeodesic({ face: [0] }), /face/);
    // Still the same distances after the refusals.
    const [a, b] = [fresh, kept].map((m) => m.geodesicDistance({ boundaryOf: 'mesh' }));
    assert.deepEqual(b.vertexDistance(), a.vertexDistance());
    a.free();
    b.free();
  } finally {
    fresh.free();
    kept.free();
  }
});

test('toolPath: a ToolPath with flat arrays and the robot exports', () => {
  const field = mesh.geodesicDistance(ringSource);
  const path = field.toolPath(10, { order: 'oneWay', pointSpacing: 5, speed: 20, linkSpeed: 200 });
  assert.ok(path instanceof ToolPath);
  const n = path.poseCount;
  assert.ok(path.passCount >= 11);
  assert.equal(path.positions().length, 3 * n);
  assert.equal(path.axes().length, 3 * n);
  assert.equal(path.kinds().length, n);
  assert.equal(path.passOf().length, n);
  // Tool axis = − outward normal: pointing at the axis of the cylinder.
  const p = path.positions();
  const a = path.axes();
  assert.ok(p[0] * a[0] + p[1] * a[1] < 0);
  const rapid = path.toRapid();
  // No two consecutive poses share a position (a link arrives at the pass's first point,
  // which is not repeated): one MoveL per pose and the retract; a MoveJ to the approach first.
  let distinct = 1;
  for (let i = 1; i < n; i++) {
    if (Math.hypot(p[3 * i] - p[3 * i - 3], p[3 * i + 1] - p[3 * i - 2], p[3 * i + 2] - p[3 * i - 1]) > 1e-9) distinct++;
  }
  assert.equal(distinct, n, 'no position repeats');
  assert.equal(rapid[0].split('\n').filter((l) => l.trim().startsWith('MoveL')).length, distinct + 1);
  assert.equal(rapid[0].split('\n').filter((l) => l.trim().startsWith('MoveJ')).length, 1);
  assert.ok(path.toKrl()[0].includes('DEF'));
  const csv = path.toCsv({ mmPerUnit: 1000 }).split('\n');
  const x = Number(csv[1].split(',')[3]);
  assert.ok(Math.abs(x - 1000 * p[0]) < 1e-3, `${x} vs ${p[0]}`);
  assert.equal(JSON.parse(path.toJson()).poseCount, n);
  // Bead width × overlap as the spacing (the paper: 6.4 × 0.738).
  const bead = field.isoPaths(null, { beadWidth: 6.4, overlapFactor: 0.738, maxLevel: 1 });
  assert.ok(Math.abs(bead[0].distance - 6.4 * 0.738) < 1e-12);
  const beadPath = field.toolPath(null, { beadWidth: 6.4, overlapFactor: 0.738 });
  assert.ok(beadPath.passCount > path.passCount);
  path.free();
  beadPath.free();
  field.free();
});

test('the TypeScript declarations name the new API', () => {
  const dts = readFileSync(join(pkg, 'skinpath.d.ts'), 'utf8');
  for (const name of ['export class DistanceField', 'export class ToolPath', 'export type GeodesicSource',
    'export interface GeodesicParams', 'export interface GeodesicPathOptions', 'export interface IsoPath',
    'geodesicDistance(source: GeodesicSource, params?: GeodesicParams', 'prepareGeodesic(params?: GeodesicParams): void', 'isoPaths(spacing: number | null, opts?: GeodesicPathOptions): IsoPath[]',
    'toolPath(spacing: number | null, opts?: GeodesicPathOptions): ToolPath', 'readonly maxDistance: number',
    'readonly method: string', 'vertexDistance(): Float64Array', 'voxelCenters(): Float32Array',
    'voxelDistance(): Float32Array', 'kinds(): Uint8Array', 'passOf(): Uint32Array']) {
    assert.ok(dts.includes(name), `d.ts lacks ${name}`);
  }
});

test('bad input throws an Error naming it and the mesh keeps working', () => {
  refuses(() => mesh.geodesicDistance({ polyline: [0, 0, 1000] }), /misses the surface/);
  refuses(() => mesh.geodesicDistance({ polyline: [0, 0] }), /^source\.polyline has 2 numbers, not a multiple of 3/);
  refuses(() => mesh.geodesicDistance({ polyline: 'abc' }), /^source\.polyline must be a Float64Array/);
  refuses(() => mesh.geodesicDistance({ polyline: [0, NaN, 0] }), /^source\.polyline\[1\] must be a finite number/);
  refuses(() => mesh.geodesicDistance({ vertices: [] }), /source\.vertices is empty/);
  refuses(() => mesh.geodesicDistance({ vertices: [1e6] }), /vertex 1000000 does not exist/);
  refuses(() => mesh.geodesicDistance({ vertexes: [0] }), /^unknown geodesic source 'vertexes'$/);
  refuses(() => mesh.geodesicDistance({}), /needs one of 'polyline', 'vertices', 'boundaryOf', 'plane'/);
  refuses(() => mesh.geodesicDistance({ vertices: [0], plane: {} }), /exactly one/);
  refuses(() => mesh.geodesicDistance({ vertices: [0], loop: 1 }), /'loop' only goes with 'boundaryOf'/);
  refuses(() => mesh.geodesicDistance({ boundaryOf: 'patch' }), /^source\.boundaryOf must be "mesh" or a patch id/);
  refuses(() => mesh.geodesicDistance({ boundaryOf: 'mesh', loop: 5 }), /loop 5 does not exist/);
  refuses(() => mesh.geodesicDistance({ boundaryOf: 2 }), /names a patch: give its triangles as params\.faces/);
  refuses(() => mesh.geodesicDistance({ plane: { point: [0, 0, 500], normal: [0, 0, 1] } }), /does not cut the surface/);
  refuses(() => mesh.geodesicDistance({ plane: { point: [0, 0, 0], normal: [0, 0, 0] } }), /non-zero normal/);
  refuses(() => mesh.geodesicDistance({ plane: { point: [0, 0] , normal: [0, 0, 1] } }), /^plane\.point must be three numbers/);
  refuses(() => mesh.geodesicDistance({ plane: { point: [0, 0, 0], normal: [0, 0, 1], up: 1 } }), /^unknown geodesic source 'plane\.up'$/);
  refuses(() => mesh.geodesicDistance(null), /^geodesic sources must be an object, got null$/);
  refuses(() => mesh.geodesicDistance(ringSource, { method: 'fmm' }), /^method must be one of "accurate", "exact", "fast", "mesh", "voxel", got the string "fmm"$/);
  refuses(() => mesh.geodesicDistance(ringSource, { methd: 'mesh' }), /^unknown geodesic parameter 'methd'$/);
  refuses(() => mesh.geodesicDistance(ringSource, { voxelSize: 1 }), /'voxelSize' needs method "voxel"/);
  refuses(() => mesh.geodesicDistance(ringSource, { method: 'voxel', voxelSize: 0.001 }), /voxel size 0\.001 is too small: .*use a voxel size of at least/);
  refuses(() => mesh.geodesicDistance(ringSource, { method: 'voxel', voxelSize: -1 }), /voxelSize = -1/);
  refuses(() => mesh.geodesicDistance(ringSource, { faces: new Uint32Array(0) }), /^faces is empty/);
  refuses(() => mesh.geodesicDistance(ringSource, { faces: [1e7] }), /face set is invalid/);
  refuses(() => mesh.geodesicDistance(ringSource, { faces: 'all' }), /^faces must be a Uint32Array/);
  refuses(() => mesh.geodesicDistance(ringSource, undefined, 'progress'), /^onProgress must be a function/);
  const field = mesh.geodesicDistance(ringSource);
  refuses(() => field.isoPaths(0), /spacing = 0 is invalid: must be finite and > 0/);
  refuses(() => field.isoPaths(-5), /spacing = -5/);
  refuses(() => field.isoPaths('10'), /^spacing must be a number/);
  refuses(() => field.isoPaths(undefined), /^spacing is missing/);
  refuses(() => field.isoPaths(10, { beadWidth: 6.4, overlapFactor: 0.7 }), /either spacing or/);
  refuses(() => field.isoPaths(null, { beadWidth: 6.4, overlapFactor: 1.5 }), /overlapFactor = 1\.5/);
  refuses(() => field.isoPaths(10, { order: 'spiral' }), /^order must be one of "zigzag", "oneWay"/);
  refuses(() => field.isoPaths(10, { levels: 3 }), /^unknown path option 'levels'$/);
  refuses(() => field.isoPaths(10, { maxLevel: 0.5 }), /^maxLevel must be a whole number/);
  refuses(() => field.isoPaths(10, { pointSpacing: 0 }), /pointSpacing = 0/);
  refuses(() => field.toolPath(1e-4), /more than 100000 levels/);
  // 12,000 levels round the cylinder, a point every 0.0025 mm: refused at 5 million points,
  // before they are made.
  refuses(() => field.isoPaths(0.01), /^the passes would need more than 5\.0 million points, the most one computation may have: widen the pass spacing or the point spacing, or ask for fewer passes/);
  refuses(() => field.toolPath(0.01), /more than 5\.0 million points/);
  refuses(() => field.toolPath(10, { speed: -1 }), /speed = -1/);
  const path = field.toolPath(10);
  refuses(() => path.toCsv({ mmPerUnit: 0 }), /mmPerUnit/);
  refuses(() => path.toRapid({ unit: 'mm' }), /^unknown export option 'unit'$/);
  // One range for every value that is not a move count (0 said "at least 1", −1 "from 0").
  for (const bad of [0, -1, 0.5]) refuses(() => path.toRapid({ maxMoves: bad }), /^maxMoves must be a whole number from 1 to 1073741824, got /);
  path.free();
  field.free();
  stillWorks();
});

test('a DistanceField outlives its freed mesh', () => {
  const own = Mesh.fromStl(cylinderStl(R, 120, N, 24));
  const field = own.geodesicDistance(ringSource);
  own.free();
  assert.ok(field.isoPaths(10).length >= 11);
  field.free();
});
