// The built wasm package as JavaScript sees it, in Node: initSync, the generated .d.ts,
// errors that are plain Errors, and a module that keeps working after a failure.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const pkg = join(root, 'dist', 'pkg');
const wasm = await import(join(pkg, 'skinpath.js'));
wasm.initSync({ module: readFileSync(join(pkg, 'skinpath_bg.wasm')) });
const { Mesh, deriveThreshold, wasmMemoryBytes } = wasm;
const fixture = (name) => readFileSync(join(root, 'tests', 'fixtures', name));
const model = (name) => readFileSync(join(root, '..', 'shared', 'models', name));
const paper = { angleThreshold: 0.35, thetaMax: 1, minAreaRatio: 0.1 };

test('the generated TypeScript declarations name the whole API', () => {
  const dts = readFileSync(join(pkg, 'skinpath.d.ts'), 'utf8');
  for (const name of ['static fromStl(bytes: Uint8Array | ArrayBuffer, onProgress?: ProgressCallback): Mesh',
    'readonly triangleCount: number', 'readonly vertexCount: number', 'positions(): Float32Array',
    'indices(): Uint32Array', 'report(): MeshReport', 'segment(params: SegmentParams, onProgress?: ProgressCallback): Segmentation',
    'readonly patchCount: number', 'readonly threshold: number', 'readonly thresholdKind: string',
    'patchOf(): Int32Array', 'patches(): Patch[]', 'borderSegments(): Float32Array', 'borderPatches(): Int32Array',
    'patchStl(id: number): Uint8Array', 'export function deriveThreshold(params: SegmentParams): Threshold;',
    'export function wasmMemoryBytes(): number', 'free(): void', 'export interface MeshReport {',
    'export interface Patch {', 'export type ProgressCallback = (stage: string, fraction: number) => void;']) {
    assert.ok(dts.includes(name), `skinpath.d.ts lacks "${name}"`);
  }
});

test('a real aircraft imports, reports and segments with progress', () => {
  const stages = new Set();
  const mesh = Mesh.fromStl(model('wingbody_79868_flow360.stl'), (stage, fraction) => {
    assert.ok(fraction >= 0 && fraction <= 1);
    stages.add(stage);
  });
  assert.deepEqual([...stages], ['parse', 'adjacency', 'orient', 'geometry']);
  const report = mesh.report();
  assert.equal(report.triangles, 79868);
  assert.equal(report.vertices, 39936);
  assert.equal(report.format, 'binary');
  assert.equal(report.boundaryEdges, 0);
  assert.equal(mesh.positions().length, 3 * 39936);
  assert.equal(mesh.indices().length, 3 * 79868);
  const seg = mesh.segment(paper, (stage) => stages.add(stage));
  assert.ok(stages.has('planarise'));
  assert.equal(seg.thresholdKind, 'angle');
  assert.equal(seg.threshold, 0.35);
  const patches = seg.patches();
  assert.equal(patches.length, seg.patchCount);
  assert.ok(patches.every((p, i) => p.id === i && p.maxDeviation < 1 && p.normal.length === 3));
  assert.ok(patches.every((p, i) => i === 0 || patches[i - 1].area >= p.area));
  const patchOf = seg.patchOf();
  assert.equal(patchOf.length, 79868);
  assert.equal(patchOf.filter((p) => p === 0).length, patches[0].triangleCount);
  const stl = seg.patchStl(0);
  assert.equal(stl.length, 84 + 50 * patches[0].triangleCount);
  const borders = seg.borderSegments();
  assert.equal(borders.length % 6, 0);
  const sides = seg.borderPatches();
  assert.equal(sides.length, borders.length / 3);
  assert.ok(sides.every((p) => p >= -1 && p < patches.length));
  seg.free();
  mesh.free();
});

test('bad files throw plain Errors and the module keeps working', () => {
  const cases = [
    ['empty.stl', /^the file is empty$/],
    ['truncated.stl', /^truncated binary STL: the header says 12 triangles but only 7 are present/],
    ['bad_number.stl', /^malformed number '1\.0\.0' at line 5 of the ASCII STL$/],
    ['png_header.stl', /^not an STL file: it does not start with 'solid'/],
    ['count_too_large.stl', /^corrupt binary STL: the header says 4000000000 triangles/],
    ['all_nan.stl', /^no usable triangles/],
  ];
  for (const [name, message] of cases) {
    assert.throws(() => Mesh.fromStl(fixture(name)), (e) => e instanceof Error && message.test(e.message)
      && !/unreachable|RuntimeError/.test(e.message));
  }
  const mesh = Mesh.fromStl(fixture('cube_ascii.stl'));
  assert.equal(mesh.segment(paper).patchCount, 6);
  assert.throws(() => mesh.segment({ ...paper, thetaMax: 4 }), /thetaMax must be in \(0, π\] radians, got 4/);
  assert.throws(() => mesh.segment({ ...paper, minAreaRatio: 'ten' }), /^Error: minAreaRatio must be a number, got the string "ten"$/);
  assert.equal(mesh.segment(paper).patchCount, 6, 'the mesh survives bad parameters');
});

test('deriveThreshold follows eq. 4 and eq. 9 and names bad parameters', () => {
  assert.deepEqual(deriveThreshold({ angleThreshold: 0.35 }), { kind: 'angle', value: 0.35 });
  const spray = deriveThreshold({ spray: { meanThickness: 100, allowedDeviation: 6, minThickness: 97 } });
  assert.equal(spray.kind, 'angle');
  assert.ok(Math.abs(spray.value - Math.acos(94 / 97)) < 1e-12);
  const grind = deriveThreshold({ grind: { indentationDepth: 0.2, minPressureRatio: 0.6, contactWidth: 8 } });
  assert.equal(grind.kind, 'curvature');
  assert.ok(Math.abs(grind.value - (2 * 0.2 * (1 - 0.36)) / 64) < 1e-12);
  assert.throws(() => deriveThreshold({ spray: { meanThickness: 100, allowedDeviation: 6, minThickness: 97, typo: 1 } }),
    /unknown segmentation parameter 'spray.typo'/);
  assert.throws(() => deriveThreshold({ angleThreshold: 0.3, curvatureThreshold: 1 }),
    /give exactly one of angleThreshold, curvatureThreshold, spray or grind \(got angleThreshold, curvatureThreshold\)/);
  assert.ok(wasmMemoryBytes() > 0 && wasmMemoryBytes() % 65536 === 0);
});
