// The drilling API of the built wasm package in Node: laser normals, simulated readings,
// closest points and hole correction, with the errors JavaScript sees.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const pkg = join(root, 'dist', 'pkg');
const wasm = await import(join(pkg, 'skinpath.js'));
wasm.initSync({ module: readFileSync(join(pkg, 'skinpath_bg.wasm')) });
const { Mesh, normalFromLasers, correctHoles } = wasm;

const R = 1000;
const HALF = Math.PI / 6;
const LENGTH = 400;
const onCylinder = (t, z) => [R * Math.sin(t), R * Math.cos(t), z];
const radial = (t) => [Math.sin(t), Math.cos(t), 0];

/** Binary STL of a cylinder panel, 80° × 600 mm in 200 facets around, moved by `place`. */
function panelStl(place = (p) => p) {
  const cells = 200;
  const rows = 6;
  const span = (40 * Math.PI) / 180;
  const at = (i, j) => place(onCylinder(-span + (2 * span * i) / cells, -100 + (600 * j) / rows));
  const tris = [];
  for (let j = 0; j < rows; j++) {
    for (let i = 0; i < cells; i++) {
      tris.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)], [at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
    }
  }
  const view = new DataView(new ArrayBuffer(84 + 50 * tris.length));
  view.setUint32(80, tris.length, true);
  tris.forEach((t, k) => t.flat().forEach((c, m) => view.setFloat32(84 + 50 * k + 12 + 4 * m, c, true)));
  return new Uint8Array(view.buffer);
}

const sub = (a, b) => a.map((x, i) => x - b[i]);
const norm = (a) => Math.hypot(...a);

/** Rotation by a small angle about z, then a shift: a rigid move of the panel. */
const angle = (0.25 * Math.PI) / 180;
const rotate = ([x, y, z]) => [x * Math.cos(angle) - y * Math.sin(angle), x * Math.sin(angle) + y * Math.cos(angle), z];
const move = (p) => sub(rotate(p), [-1.5, 2, -1]);

const corners = [[-HALF, 0], [HALF, 0], [HALF, LENGTH], [-HALF, LENGTH]];
const holeParams = [];
for (let j = 1; j <= 4; j++) for (let i = 1; i <= 4; i++) holeParams.push([-HALF + (2 * HALF * i) / 5, (LENGTH * j) / 5]);
const params = (extra = {}) => ({
  references: corners.map(([t, z]) => ({
    nominal: onCylinder(t, z), actual: move(onCylinder(t, z)), normal: rotate(radial(t)), nominalNormal: radial(t),
  })),
  holes: new Float64Array(holeParams.flatMap(([t, z]) => onCylinder(t, z))),
  ...extra,
});
const truth = holeParams.map(([t, z]) => move(onCylinder(t, z)));
const maxError = (flat) => Math.max(...truth.map((q, k) => norm(sub(Array.from(flat.slice(3 * k, 3 * k + 3)), q))));

test('the TypeScript declarations name the drilling API', () => {
  const dts = readFileSync(join(pkg, 'skinpath.d.ts'), 'utf8');
  for (const name of ['export function normalFromLasers(', ': [number, number, number]', 'laserReadings(',
    'closestPoints(points: Float64Array | number[]): ClosestPoints', 'export function correctHoles(params: CorrectionParams): HoleCorrection',
    'correctHoles(params: CorrectionParams): HoleCorrection;', 'export interface HoleCorrection {',
    'export interface CorrectionParams {', 'export interface ReferenceHole {', 'export interface ClosestPoints {',
    'export function parseHolesCsv(text: string): HoleList;', 'export function drillPaperExample(): DrillPaperExample;',
    'drillingProgram(params: CorrectionParams, pose: DrillPoseParams | undefined, format: string, options: ExportOptions | undefined): string[];',
    'export interface HoleList {', 'export interface DrillPoseParams {', 'export interface DrillPaperExample {']) {
    assert.ok(dts.includes(name), `skinpath.d.ts lacks "${name}"`);
  }
});

test('normalFromLasers: a square head over a plane, and refusals as Errors', () => {
  const origins = new Float64Array([0, 0, 10, 1, 0, 10, 1, 1, 10, 0, 1, 10]);
  const down = new Float64Array([0, 0, -1, 0, 0, -1, 0, 0, -1, 0, 0, -1]);
  const n = normalFromLasers(origins, down, new Float64Array([10, 10, 10, 10]));
  assert.deepEqual(n.map((x) => x + 0), [0, 0, 1]);
  const line = new Float64Array([0, 0, 10, 1, 0, 10, 2, 0, 10, 3, 0, 10]);
  assert.throws(() => normalFromLasers(line, down, new Float64Array([10, 10, 10, 10])), (e) => e instanceof Error && /collinear/.test(e.message));
  assert.throws(() => normalFromLasers(origins, down, new Float64Array([10, NaN, 10, 10])), /^Error: readings\[1\] must be a finite number, got NaN$/);
  assert.throws(() => normalFromLasers(origins, down, new Float64Array([10, 10, 10])), /readings must hold 4/);
  // Arrays of numbers are read as they are; nothing else is turned into numbers (null was
  // read as 0, '10' as 10, and the string '1111' as four readings of 1).
  assert.deepEqual(normalFromLasers(Array.from(origins), Array.from(down), [10, 10, 10, 10]).map((x) => x + 0), [0, 0, 1]);
  assert.throws(() => normalFromLasers(origins, down, [10, null, 10, 10]), /^Error: readings\[1\] must be a number, got null$/);
  assert.throws(() => normalFromLasers(origins, down, [10, '10', 10, 10]), /^Error: readings\[1\] must be a number, got the string "10"$/);
  assert.throws(() => normalFromLasers(origins, down, '1111'), /^Error: readings must be a Float64Array or an array of numbers, got the string "1111"$/);
  const tilted = Array.from(origins);
  tilted[11] = true;
  assert.throws(() => normalFromLasers(tilted, down, [10, 10, 10, 10]), /^Error: origins\[11\] must be a number, got true$/);
});

test('laser readings and closest points on a cylinder panel', () => {
  const mesh = Mesh.fromStl(panelStl());
  try {
    // Beams straight down the radius from 50 mm outside, and one pointing away (a miss).
    const ts = [-0.3, 0, 0.2, 0.45];
    const origins = new Float64Array(ts.flatMap((t) => onCylinder(t, 200).map((c, i) => c + 50 * radial(t)[i])));
    const directions = new Float64Array(ts.flatMap((t, k) => radial(t).map((c) => (k === 3 ? c : -c))));
    const r = mesh.laserReadings(origins, directions);
    assert.ok(r instanceof Float64Array && r.length === 4);
    for (const k of [0, 1, 2]) assert.ok(Math.abs(r[k] - 50) < 0.02, `reading ${r[k]}`);
    assert.ok(Number.isNaN(r[3]));
    assert.throws(() => mesh.laserReadings(origins, new Float64Array(12)), /direction of beam 1 must be a unit vector/);
    assert.throws(() => mesh.laserReadings(origins, Array.from(directions, (x, i) => (i === 4 ? null : x))), /^Error: directions\[4\] must be a number, got null$/);
    assert.throws(() => mesh.closestPoints([0, 0, 'x']), /^Error: points\[2\] must be a number, got the string "x"$/);
    assert.throws(() => mesh.closestPoints([0, 0, NaN]), /^Error: points\[2\] must be a finite number, got NaN$/);
    assert.deepEqual(Array.from(mesh.laserReadings(Array.from(origins), Array.from(directions)), (x) => Number.isNaN(x) ? 'miss' : Math.round(x)),
      [50, 50, 50, 'miss'], 'arrays of numbers are read as typed arrays are');
    const c = mesh.closestPoints(origins.slice(0, 9));
    assert.equal(c.points.length, 9);
    for (const k of [0, 1, 2]) {
      assert.ok(Math.abs(c.distances[k] - 50) < 0.02, `distance ${c.distances[k]}`);
      const n = Array.from(c.normals.slice(3 * k, 3 * k + 3));
      const along = Math.abs(n.reduce((s, x, i) => s + x * radial(ts[k])[i], 0));
      assert.ok(along > 0.9999, `normal ${n}`);
    }
  } finally {
    mesh.free();
  }
});

test('correctHoles: a rigid move of the panel is reproduced, Coons beats bilinear', () => {
  const uncorrected = maxError(params().holes);
  const coons = correctHoles(params());
  const bilinear = correctHoles(params({ method: 'bilinear' }));
  for (const key of ['corrected', 'normals', 'u', 'w']) assert.ok(coons[key] instanceof Float64Array, key);
  assert.ok(coons.outside instanceof Uint8Array && coons.outside.every((o) => o === 0));
  assert.equal(coons.corrected.length, 48);
  const [e0, e1, e2] = [uncorrected, maxError(bilinear.corrected), maxError(coons.corrected)];
  assert.ok(e0 > 2 && e0 > e1 && e1 > e2 && e2 < 1e-3, `${e0} ${e1} ${e2}`);
  const mesh = Mesh.fromStl(panelStl(move));
  try {
    // On the moved panel's mesh: projection adds at most the facets' sag (6e-3 mm) and f32
    // rounding; the normals are the mesh's, pointing outwards.
    const projected = mesh.correctHoles(params());
    assert.equal(projected.corrected.length, 48);
    assert.ok(maxError(projected.corrected) < 0.01, `${maxError(projected.corrected)}`);
    const n = Array.from(projected.normals.slice(0, 3));
    const p = Array.from(projected.corrected.slice(0, 3));
    assert.ok((n[0] * p[0] + n[1] * p[1]) / Math.hypot(p[0], p[1]) > 0.999, `${n}`);
  } finally {
    mesh.free();
  }
});

test('correctHoles refuses bad parameters with the reason', () => {
  assert.throws(() => correctHoles(params({ extra: 1 })), /^Error: unknown hole-correction parameter 'extra'$/);
  const typo = params();
  typo.references[1].nominalNormals = [0, 1, 0];
  assert.throws(() => correctHoles(typo), /^Error: unknown hole-correction parameter 'references\[1\]\.nominalNormals'$/);
  assert.throws(() => correctHoles(params({ method: 'spline' })), /^Error: method must be one of "coons", "bilinear", got the string "spline"$/);
  assert.throws(() => correctHoles({ ...params(), references: params().references.slice(0, 3) }), /^Error: references must list exactly 4 entries, got 3$/);
  assert.throws(() => correctHoles(params({ holes: new Float64Array([1, 2]) })), /holes has 2 numbers, not a multiple of 3/);
  // Cycles, throwing getters and nulls are refused by name, never followed.
  const cyclic = params();
  cyclic.references[0].self = cyclic;
  assert.throws(() => correctHoles(cyclic), /^Error: unknown hole-correction parameter 'references\[0\]\.self'$/);
  const throwing = params();
  Object.defineProperty(throwing.references[2], 'normal', { get() { throw new Error('boom'); }, enumerable: true });
  assert.throws(() => correctHoles(throwing), /^Error: reading hole-correction parameter 'references\[2\]\.normal' threw: boom$/);
  assert.throws(() => correctHoles(params({ tangentScale: null })), /^Error: tangentScale must be a number, got null$/);
  assert.throws(() => correctHoles(null), /^Error: hole-correction parameters must be an object, got null$/);
  const outside = new Float64Array(onCylinder(HALF + 0.1, 200));
  assert.throws(() => correctHoles(params({ holes: outside })), /outside the reference quadrilateral/);
  const flagged = correctHoles(params({ holes: outside, extrapolate: true }));
  assert.deepEqual(Array.from(flagged.outside), [1]);
  const refs = params().references;
  refs[2].nominal = refs[1].nominal;
  assert.throws(() => correctHoles({ ...params(), references: refs }), /B and C coincide/);
});

test('parseHolesCsv keeps the good rows and reports bad ones by line', () => {
  const list = wasm.parseHolesCsv('id,x,y,z\nH1, 1, 2, 3\n\nH2,4,five,6\nH3,7,8\nH4,10,11,12\n');
  assert.deepEqual(list.ids, ['H1', 'H4']);
  assert.deepEqual(Array.from(list.positions), [1, 2, 3, 10, 11, 12]);
  assert.deepEqual(Array.from(list.lines), [2, 6]);
  assert.equal(list.header, true);
  assert.deepEqual(list.errors.map((e) => e.line), [4, 5]);
  assert.match(list.errors[0].message, /y = "five" is not a finite number/);
  // Anything but a string is named (a number made the generated glue write out of bounds: a
  // trap), and the engine keeps working.
  for (const [bad, shown] of [[42, 'the number 42'], [null, 'null'], [undefined, 'undefined'], [['a,1,2,3'], 'an array'], [true, 'true']]) {
    assert.throws(() => wasm.parseHolesCsv(bad),
      (e) => e instanceof Error && !(e instanceof WebAssembly.RuntimeError) && e.message === `parseHolesCsv: text must be a string, got ${shown}`);
  }
  assert.deepEqual(wasm.parseHolesCsv('H9,1,2,3').ids, ['H9']);
});

test('drillPaperExample gives the panel, the references and the truth; drillingProgram writes it', () => {
  const ex = wasm.drillPaperExample();
  assert.equal(ex.ids.length, 16);
  assert.equal(ex.holes.length, 48);
  assert.equal(ex.truth.length, 48);
  assert.equal(ex.references.length, 4);
  const mesh = Mesh.fromStl(ex.stl);
  try {
    const params = { references: ex.references, holes: ex.holes };
    const err = (c) => Math.max(...ex.ids.map((_, i) => norm(sub(c.slice(3 * i, 3 * i + 3), ex.truth.slice(3 * i, 3 * i + 3)))));
    const coons = err(mesh.correctHoles(params).corrected);
    const bilinear = err(mesh.correctHoles({ ...params, method: 'bilinear' }).corrected);
    assert.ok(err(ex.holes) > bilinear && bilinear > 10 * coons, `${err(ex.holes)} ${bilinear} ${coons}`);
    const [rapid] = mesh.drillingProgram(params, { approach: 15 }, 'rapid', { name: 'dr_test' });
    // The 48 poses, the retract after them, and one joint move to the approach pose first.
    assert.equal((rapid.match(/MoveL /g) ?? []).length, 48 + 1);
    assert.equal((rapid.match(/MoveJ /g) ?? []).length, 1);
    const [csv] = mesh.drillingProgram(params, undefined, 'csv', undefined);
    assert.equal(csv.trim().split('\n').length, 1 + 48);
    assert.throws(() => mesh.drillingProgram(params, undefined, 'gcode', undefined), /unknown export format "gcode"/);
    // Not a string: named, not a trap of the generated glue (it wrote out of bounds).
    for (const [bad, shown] of [[42, 'the number 42'], [null, 'null'], [{}, 'an object']]) {
      assert.throws(() => mesh.drillingProgram(params, undefined, bad, undefined),
        (e) => e instanceof Error && !(e instanceof WebAssembly.RuntimeError) && e.message === `unknown export format ${shown} (allowed: csv, json, rapid, krl)`);
    }
    assert.throws(() => mesh.drillingProgram(params, { approach: -1 }, 'csv', undefined), /approach/);
    assert.throws(() => mesh.drillingProgram(params, { approch: 1 }, 'csv', undefined), /approch/);
  } finally {
    mesh.free();
  }
});
