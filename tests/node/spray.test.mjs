// Mesh.planSpray from the built wasm package in Node: shapes of the flat arrays, the quality
// figures, the spacing search's iterations, the gun speeds, cycle time, lengths, worst
// regions and directions tried, errors naming bad parameters, and patchFaces.
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
  assert.deepEqual(Object.keys(its[0]).sort(), ['error', 'full', 'mean', 'met', 'resolution', 'spacing', 'stdDev']);
  assert.equal(its[0].full, true, 'without a search the one spacing is at full resolution');
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
  // Constant speed: with the optimiser on, the widest spacing already meets this limit.
  const plan = mesh.planSpray({ ...base, optimiseSpeed: false, timeStep: 0.05, quality: { maxError: 0.1, minSpacing: 25 } });
  const its = plan.iterations();
  // At least one coarse spacing, a refinement on the coarse samples and the confirmation.
  assert.ok(its.length >= 3, `${its.length} tried`);
  const q = plan.quality();
  assert.equal(q.limitsMet, true);
  assert.ok(q.interior.error <= 0.1);
  // The choice rests on the full resolution (the finest); the scan may run coarser.
  const res = Math.min(...its.map((it) => it.resolution));
  const full = its.filter((it) => it.resolution === res);
  assert.deepEqual(its.map((it) => it.full), its.map((it) => it.resolution === res), 'full marks the full-resolution figures');
  assert.ok(full.length >= 1 && full.length < its.length, 'screened on coarse samples, confirmed at full');
  assert.ok(full.some((it) => it.spacing === plan.spacing && it.met));
  assert.ok(!full.some((it) => it.met && it.spacing > plan.spacing));
  const impossible = mesh.planSpray({ ...base, timeStep: 0.05, quality: { maxError: 1e-9, minSpacing: 40 } });
  assert.equal(impossible.quality().limitsMet, false);
  assert.match(impossible.quality().messages.join(' '), /not met/);
  plan.free();
  impossible.free();
  mesh.free();
});

/** Length of the move arriving at each point (0 for the first), from the flat trajectory. */
function moveLengths(traj) {
  const n = traj.length / 6;
  const out = new Float64Array(n);
  for (let i = 1; i < n; i++) {
    out[i] = Math.hypot(traj[6 * i] - traj[6 * i - 6], traj[6 * i + 1] - traj[6 * i - 5], traj[6 * i + 2] - traj[6 * i - 4]);
  }
  return out;
}

test('the plan carries a speed per point within the limits, its cycle time, lengths and worst regions', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 8, 6));
  const limits = { minSpeed: 60, maxSpeed: 180 };
  const plan = mesh.planSpray({ ...base, ...limits, timeStep: 0.05, quality: { maxError: 0.1, minSpacing: 25 } });
  assert.equal(plan.speedOptimised, true, 'on by default');
  const kinds = plan.pointKinds();
  const speeds = plan.speeds();
  assert.ok(speeds instanceof Float64Array);
  assert.equal(speeds.length, kinds.length, 'one speed per trajectory point');
  assert.ok(speeds.every((v) => Number.isFinite(v) && v > 0));
  const gunOn = [...speeds].filter((_, i) => i > 0 && kinds[i] <= 3);
  assert.ok(gunOn.length > 0);
  const lo = Math.min(...gunOn);
  const hi = Math.max(...gunOn);
  assert.equal(plan.minSpeed, lo, 'minSpeed is the slowest gun-on move');
  assert.equal(plan.maxSpeed, hi, 'maxSpeed is the fastest gun-on move');
  assert.ok(lo >= limits.minSpeed * (1 - 1e-12) && hi <= limits.maxSpeed * (1 + 1e-12), `${lo}–${hi}`);
  assert.ok(hi > lo, 'the speed varies along the passes');
  // Lengths and cycle time against the trajectory itself: Σ|move| and Σ|move| / speed.
  const lengths = moveLengths(plan.trajectory());
  let spray = 0;
  let whole = 0;
  let time = 0;
  for (let i = 1; i < kinds.length; i++) {
    whole += lengths[i];
    if (kinds[i] <= 3) spray += lengths[i];
    time += lengths[i] / speeds[i];
  }
  assert.ok(Math.abs(plan.pathLength - whole) <= 1e-9 * whole, `${plan.pathLength} vs ${whole}`);
  assert.ok(Math.abs(plan.sprayLength - spray) <= 1e-9 * spray, `${plan.sprayLength} vs ${spray}`);
  assert.ok(plan.sprayLength < plan.pathLength);
  assert.ok(plan.cycleTime > 0);
  assert.ok(Math.abs(plan.cycleTime - time) <= 1e-6 * time, `cycle ${plan.cycleTime} s vs Σ length/speed ${time} s`);
  assert.equal(plan.rasterAngle, 0);
  assert.deepEqual(plan.directions(), [], 'no directions tried without bestDirection');
  const its = plan.iterations();
  assert.ok(its.every((it) => typeof it.full === 'boolean'));
  assert.ok(its.some((it) => it.full && it.spacing === plan.spacing), 'the chosen spacing was confirmed at full resolution');
  const spots = plan.hotspots();
  assert.ok(Array.isArray(spots) && spots.length >= 1);
  for (const h of spots) {
    assert.deepEqual(Object.keys(h).sort(), ['cause', 'deviation', 'position']);
    assert.equal(h.position.length, 3);
    assert.ok(h.position.every(Number.isFinite));
    assert.ok(h.position[0] >= -1e-9 && h.position[0] <= 400 + 1e-9 && h.position[1] >= -1e-9 && h.position[1] <= 300 + 1e-9);
    assert.ok(Math.abs(h.position[2]) < 1e-6, 'on the plate');
    assert.ok(Number.isFinite(h.deviation));
    assert.ok(['edge', 'fold', 'curvature', 'spacing'].includes(h.cause), h.cause);
    assert.notEqual(h.cause, 'fold', 'a flat plate has no fold');
  }
  for (let k = 1; k < spots.length; k++) assert.ok(Math.abs(spots[k - 1].deviation) >= Math.abs(spots[k].deviation), 'worst first');
  plan.free();

  // Off: one speed on every gun-on move, the nominal one (no target given).
  const uniform = mesh.planSpray({ ...base, ...limits, optimiseSpeed: false });
  assert.equal(uniform.speedOptimised, false);
  const u = uniform.speeds();
  const k2 = uniform.pointKinds();
  assert.equal(u.length, k2.length);
  assert.ok([...u].every((v, i) => i === 0 || k2[i] > 3 || v === base.speed), 'uniform gun-on speed');
  assert.equal(uniform.minSpeed, base.speed);
  assert.equal(uniform.maxSpeed, base.speed);
  uniform.free();
  mesh.free();
});

test('bestDirection reports the four directions tried and uses the chosen one', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 8, 6));
  const plan = mesh.planSpray({ ...base, bestDirection: true });
  const trials = plan.directions();
  assert.equal(trials.length, 4);
  for (const d of trials) assert.deepEqual(Object.keys(d).sort(), ['chosen', 'cycleTime', 'error', 'rasterAngle', 'stdDev']);
  const turns = trials.map((d) => Math.round((d.rasterAngle * 180) / Math.PI)).sort((a, b) => a - b);
  assert.deepEqual(turns, [-45, 0, 45, 90]);
  const chosen = trials.filter((d) => d.chosen);
  assert.equal(chosen.length, 1);
  assert.equal(plan.rasterAngle, chosen[0].rasterAngle);
  assert.ok(chosen[0].cycleTime > 0);
  plan.free();
  mesh.free();
});

test('a nominal speed outside the speed limits throws an Error naming them', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 4, 3));
  for (const change of [{ minSpeed: 150 }, { maxSpeed: 50 }, { minSpeed: 120, maxSpeed: 110 }]) {
    assert.throws(() => mesh.planSpray({ ...base, ...change }),
      (e) => e instanceof Error && /minSpeed|maxSpeed/.test(e.message) && !/unreachable|RuntimeError/.test(e.message),
      JSON.stringify(change));
  }
  assert.throws(() => mesh.planSpray({ ...base, minSpeed: -1 }), /minSpeed must be positive/);
  assert.throws(() => mesh.planSpray({ ...base, optimiseSpeed: 'yes' }), /^Error: optimiseSpeed must be true or false/);
  const plan = mesh.planSpray({ ...base, minSpeed: 100, maxSpeed: 100 });
  assert.equal(plan.minSpeed, 100);
  plan.free();
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

test('sampleBudget coarsens the resolution until the samples fit; plan.resolution says which', () => {
  const mesh = Mesh.fromStl(plateStl(400, 300, 4, 3));
  try {
    const fine = mesh.planSpray(base);
    assert.equal(fine.resolution, 12.5);
    const all = fine.samplePositions().length / 3;
    fine.free();
    // The budget counts samples on shared edges twice (an upper bound): 3 × all is enough.
    for (const budget of [3 * all, all, 300]) {
      const plan = mesh.planSpray({ ...base, sampleBudget: budget });
      const samples = plan.samplePositions().length / 3;
      assert.ok(samples <= budget, `${samples} samples for a budget of ${budget}`);
      if (budget > all) assert.equal(plan.resolution, 12.5);
      else assert.ok(plan.resolution > 12.5 && samples < all, `${budget}: resolution ${plan.resolution}`);
      plan.free();
    }
    // Not below what the faces' vertices give: the resolution that leaves them unsplit.
    const least = mesh.planSpray({ ...base, sampleBudget: 1 });
    assert.equal(least.samplePositions().length / 3, 20);
    assert.ok(least.resolution >= 100);
    least.free();
    for (const bad of [0, 1.5, -3, '100', NaN]) {
      assert.throws(() => mesh.planSpray({ ...base, sampleBudget: bad }), /sampleBudget/);
    }
  } finally {
    mesh.free();
  }
});

test('plans on the samples the mesh keeps are the plans on a fresh mesh', () => {
  // The mesh keeps the samples of its last plan for the next on the same faces: a change of
  // spacing, speed, limits or direction plans on them; other faces or another footprint
  // make new ones. Every figure must match a fresh mesh's, to the bit.
  const bytes = plateStl(400, 300, 8, 6);
  const kept = Mesh.fromStl(bytes);
  const left = Uint32Array.from({ length: kept.triangleCount / 2 }, (_, f) => f);
  const search = { quality: { maxError: 0.1, minSpacing: 25 } };
  const steps = [
    [{}, undefined],
    [{ spacing: 40 }, undefined],
    [{ speed: 80, ...search }, undefined],
    [{ rasterAngle: 0.4, ...search }, undefined],
    [{ ...search }, left],
    [{ standoff: 120 }, left],
    [{ spacing: -1 }, left],
    [{ optimiseSpeed: false }, undefined],
  ];
  try {
    for (const [change, faces] of steps) {
      const what = JSON.stringify({ change, faces: faces?.length });
      const fresh = Mesh.fromStl(bytes);
      const plans = [];
      try {
        for (const mesh of [fresh, kept]) {
          try {
            plans.push(mesh.planSpray({ ...base, timeStep: 0.05, ...change }, faces));
          } catch (e) {
            plans.push(e);
          }
        }
      } finally {
        fresh.free();
      }
      const [a, b] = plans;
      if (a instanceof Error) {
        assert.ok(b instanceof Error, what);
        assert.equal(b.message, a.message, what);
        continue;
      }
      for (const f of ['sampleThickness', 'samplePositions', 'trajectory', 'speeds', 'iterations', 'quality']) {
        assert.deepEqual(b[f](), a[f](), `${what}: ${f}`);
      }
      a.free();
      b.free();
    }
  } finally {
    kept.free();
  }
});

test("the page's warm-up runs a spray search through screening, confirmation and the speed optimiser", async () => {
  // The worker's warm-up (www/worker/warm-up.js) must make the code of a real plan hot: the
  // samples, the search's coarse screening and full confirmation, the optimised speeds.
  const { capStl, SPRAY_WARM_UP } = await import(join(root, 'dist', 'worker', 'warm-up.js'));
  const cap = Mesh.fromStl(capStl(...SPRAY_WARM_UP.cap));
  try {
    const plan = cap.planSpray(SPRAY_WARM_UP.params);
    const its = plan.iterations();
    assert.ok(its.some((it) => !it.full) && its.some((it) => it.full), 'screened and confirmed');
    assert.ok(its.length >= 4, `${its.length} spacings tried`);
    assert.ok(plan.maxSpeed > plan.minSpeed, 'speeds optimised along the passes');
    assert.ok(plan.passCount > 1);
    plan.free();
  } finally {
    cap.free();
  }
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
    'quality(): SprayQuality', 'iterations(): SprayIteration[]', 'speeds(): Float64Array',
    'hotspots(): SprayHotspot[]', 'directions(): SprayDirectionTrial[]', 'readonly cycleTime: number',
    'readonly speedOptimised: boolean', 'readonly minSpeed: number', 'readonly maxSpeed: number', 'toCsv(opts?: ExportOptions): string', 'toJson(opts?: ExportOptions): string',
    'toRapid(opts?: ExportOptions): string[]', 'toKrl(opts?: ExportOptions): string[]',
    'readonly passCount: number', 'readonly resolution: number', 'sampleBudget?: number;', 'export interface SprayPlanParams {']) {
    assert.ok(dts.includes(name), `skinpath.d.ts lacks "${name}"`);
  }
});
