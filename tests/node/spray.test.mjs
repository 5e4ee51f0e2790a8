// Mesh.planSpray from the built wasm package in Node: shapes of the flat arrays, the quality
// figures, the spacing search's iterations, errors naming bad parameters, and patchFaces.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const pkg = join(root, 'dist', 'pkg');
const wasm = await import(join(pkg, 'skinpath.js'));
wasm.initSync({ module: readFileSync(join(pkg, 'skinpath_bg.wasm')) });
const { Mesh } = wasm;

/** Binary STL of a w × d plate in the z = 0 plane, n × m squares, normals +z. */
function plateStl(w, d, n, m) {
  const tris = [];
  const p = (i, j) => [(w * i) / n, (d * j) / m, 0];
  for (let j = 0; j < m; j++) {
    for (let i = 0; i < n; i++) {
      tris.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)], [p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
    }
  }
  const bytes = new Uint8Array(84 + 50 * tris.length);
  const view = new DataView(bytes.buffer);
  view.setUint32(80, tris.length, true);
  tris.forEach((t, k) => {
    t.flat().forEach((c, q) => view.setFloat32(84 + 50 * k + 12 + 4 * q, c, true));
  });
  return bytes;
}

// Millimetres: h 100, R = h·tan(α/2) = 50.
const base = {
  spacing: 50, standoff: 100, speed: 100, flowRate: 1000, coneAngle: 2 * Math.atan(0.5),
  transitionAngle: 0.35, efficiency: 1, resolution: 12.5,
};

test('planSpray on a plate gives consistent flat arrays and quality figures', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 4, 3));
  const stages = new Set();
  const plan = mesh.planSpray(base, undefined, (stage, fraction) => {
    assert.ok(fraction >= 0 && fraction <= 1);
    stages.add(stage);
  });
  assert.ok(stages.has('spray samples') && stages.has('spray plan'));
  assert.equal(plan.spacing, 50);
  assert.equal(plan.speed, 100);
  assert.equal(plan.passCount, 6); // ceil(300 / 50)
  const kinds = plan.pointKinds();
  const n = kinds.length;
  assert.ok(kinds instanceof Uint8Array && n > 0);
  const traj = plan.trajectory();
  assert.ok(traj instanceof Float64Array);
  assert.equal(traj.length, 6 * n);
  for (let i = 0; i < n; i++) {
    const [ax, ay, az] = traj.slice(6 * i + 3, 6 * i + 6);
    assert.ok(Math.abs(Math.hypot(ax, ay, az) - 1) < 1e-9);
    assert.ok(az < -0.999, 'the gun points down at the plate');
    assert.ok(Math.abs(traj[6 * i + 2] - 100) < 1e-6, 'at the standoff');
  }
  assert.ok(kinds.every((k) => k <= 4));
  assert.equal(kinds.filter((k) => k === 4).length, plan.passCount, 'one link per pass');
  const passOf = plan.passOf();
  assert.equal(passOf.length, n);
  assert.equal(Math.max(...passOf) + 1, plan.passCount);
  const positions = plan.samplePositions();
  const thickness = plan.sampleThickness();
  const triangles = plan.sampleTriangles();
  assert.ok(positions instanceof Float32Array && thickness instanceof Float32Array);
  assert.ok(triangles instanceof Uint32Array);
  assert.equal(positions.length, 3 * thickness.length);
  assert.equal(triangles.length % 3, 0);
  assert.ok(triangles.every((i) => i < thickness.length));
  assert.ok(thickness.every((t) => t >= 0));
  const q = plan.quality();
  for (const s of [q.interior, q.whole]) {
    assert.deepEqual(Object.keys(s).sort(), ['area', 'error', 'max', 'mean', 'min', 'stdDev']);
    assert.ok(s.min <= s.mean && s.mean <= s.max && s.stdDev >= 0);
  }
  assert.ok(Math.abs(q.whole.area - 400 * 300) < 1e-6);
  assert.ok(q.interior.area < q.whole.area);
  assert.equal(q.limitsMet, true);
  const its = plan.iterations();
  assert.equal(its.length, 1);
  assert.deepEqual(Object.keys(its[0]).sort(), ['error', 'mean', 'met', 'resolution', 'spacing', 'stdDev']);
  assert.equal(typeof plan.toCsv(), 'string');
  assert.equal(typeof plan.toJson(), 'string');
  // Exports are in mm: a file in metres scales by mmPerUnit 1000.
  const x = plan.trajectory()[0];
  const csvX = Number(plan.toCsv({ mmPerUnit: 1000 }).split('\n')[1].split(',')[3]);
  assert.ok(Math.abs(csvX - 1000 * x) < 1e-3, `${csvX} vs ${x}`);
  assert.equal(JSON.parse(plan.toJson({ mmPerUnit: 1000 })).poses[0].position[0].toFixed(3), (1000 * x).toFixed(3));
  assert.throws(() => plan.toCsv({ mmPerUnit: -1 }), /mm_per_unit|mmPerUnit/);
  assert.ok(Array.isArray(plan.toRapid({ mmPerUnit: 1, name: 'plate', maxMoves: 100 })));
  assert.ok(Array.isArray(plan.toKrl()));
  assert.throws(() => plan.toRapid({ mmPerUnit: 1, nmae: 'x' }), /^Error: unknown export option 'nmae'$/);
  plan.free();
  mesh.free();
});

test('the spacing search meets a limit and reports every spacing tried', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 4, 3));
  const plan = mesh.planSpray({ ...base, timeStep: 0.05, quality: { maxError: 0.1, minSpacing: 25 } });
  const its = plan.iterations();
  // At least one coarse spacing, its confirmation and one refinement round of two.
  assert.ok(its.length >= 4, `${its.length} tried`);
  const q = plan.quality();
  assert.equal(q.limitsMet, true);
  assert.ok(q.interior.error <= 0.1);
  // The choice rests on the full resolution (the finest); the scan may run coarser.
  const res = Math.min(...its.map((it) => it.resolution));
  const full = its.filter((it) => it.resolution === res);
  assert.ok(full.length > 1);
  assert.ok(full.some((it) => it.spacing === plan.spacing && it.met));
  assert.ok(!full.some((it) => it.met && it.spacing > plan.spacing));
  const impossible = mesh.planSpray({ ...base, timeStep: 0.05, quality: { maxError: 1e-9, minSpacing: 40 } });
  assert.equal(impossible.quality().limitsMet, false);
  assert.match(impossible.quality().messages.join(' '), /not met/);
  plan.free();
  impossible.free();
  mesh.free();
});

test('bad parameters and face lists throw Errors naming them; the mesh keeps working', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 4, 3));
  const cases = [
    [{ standoff: 0 }, /standoff must be positive/],
    [{ speed: -1 }, /speed must be positive/],
    [{ coneAngle: 4 }, /coneAngle must be in \(0, π\)/],
    [{ efficiency: 2 }, /efficiency must be in \(0, 1\]/],
    [{ spacing: 1000 }, /spacing 1000 is larger than the patch/],
    [{ quality: { maxStdDev: -1 } }, /quality\.maxStdDev must be positive/],
    [{ quality: { maxError: 0.1, typo: 1 } }, /^unknown spray parameter 'quality\.typo'$/],
    [{ spacnig: 3 }, /^unknown spray parameter 'spacnig'$/],
    [{ speed: '400' }, /^speed must be a number, got the string "400"$/],
    [{ direction: [1, 0] }, /^direction must be three numbers \[x, y, z\]/],
    [{ quality: null }, /^quality must be an object, got null$/],
    [{ resolution: 0.001 }, /coarser resolution/],
  ];
  for (const [change, message] of cases) {
    assert.throws(() => mesh.planSpray({ ...base, ...change }),
      (e) => e instanceof Error && message.test(e.message) && !/unreachable|RuntimeError/.test(e.message),
      JSON.stringify(change));
  }
  assert.throws(() => mesh.planSpray(base, new Uint32Array([])), /faces is empty/);
  assert.throws(() => mesh.planSpray(base, new Uint32Array([0, 99])), /faces contains 99/);
  assert.throws(() => mesh.planSpray(base, [0, 1.5]), /^Error: faces\[1\] must be a whole number from 0 to 4294967295, got 1\.5$/);
  assert.throws(() => mesh.planSpray(base, 'all'), /^Error: faces must be a Uint32Array or an array of face ids, got the string "all"$/);
  assert.throws(() => mesh.planSpray(base, undefined, 5), /^Error: onProgress must be a function, got the number 5$/);
  const plan = mesh.planSpray(base, new Uint32Array([0, 1, 2, 3, 4, 5, 6, 7]));
  assert.ok(plan.passCount > 0);
  plan.free();
  mesh.free();
});

test('patchFaces lists the triangles of a kept patch', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 4, 3));
  const seg = mesh.segment({ angleThreshold: 0.35 });
  const faces = seg.patchFaces(0);
  assert.ok(faces instanceof Uint32Array);
  assert.equal(faces.length, 24);
  assert.throws(() => seg.patchFaces(5), /no patch 5/);
  const plan = mesh.planSpray(base, faces);
  assert.equal(plan.passCount, 6);
  plan.free();
  seg.free();
  mesh.free();
});

test('the TypeScript declarations name the spray API', () => {
  const dts = readFileSync(join(pkg, 'skinpath.d.ts'), 'utf8');
  for (const name of ['planSpray(params: SprayPlanParams', 'patchFaces(id: number): Uint32Array',
    'trajectory(): Float64Array', 'pointKinds(): Uint8Array', 'passOf(): Uint32Array',
    'samplePositions(): Float32Array', 'sampleThickness(): Float32Array', 'sampleTriangles(): Uint32Array',
    'quality(): SprayQuality', 'iterations(): SprayIteration[]', 'toCsv(opts?: ExportOptions): string', 'toJson(opts?: ExportOptions): string',
    'toRapid(opts?: ExportOptions): string[]', 'toKrl(opts?: ExportOptions): string[]',
    'readonly passCount: number', 'export interface SprayPlanParams {']) {
    assert.ok(dts.includes(name), `skinpath.d.ts lacks "${name}"`);
  }
});
