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
const { Mesh, StlReader, deriveThreshold, wasmMemoryBytes } = wasm;
const { capStl } = await import(join(root, 'www', 'worker', 'warm-up.js'));
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
    'raycast(origin: Float64Array | number[], direction: Float64Array | number[]): RayHit | null',
    'raycast(origin: Float64Array | number[], direction: Float64Array | number[], hidden?: number[]): RayHit | null',
    'export interface RayHit {',
    'export function wasmMemoryBytes(): number', 'free(): void', 'export interface MeshReport {',
    'export interface Patch {', 'displayBuffers(onProgress?: ProgressCallback): DisplayBuffers',
    'export interface DisplayBuffers {', 'constructor(byteLength: number, onProgress?: ProgressCallback);',
    'push(bytes: Uint8Array | ArrayBuffer): void', 'finish(): Mesh', 'readonly received: number',
    'export type ProgressCallback = (stage: string, fraction: number) => void;']) {
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

/** Binary STL of flat float triples (9 per triangle). */
function stlOf(triangles) {
  const count = triangles.length / 9;
  const view = new DataView(new ArrayBuffer(84 + 50 * count));
  view.setUint32(80, count, true);
  for (let t = 0; t < count; t++) {
    for (let k = 0; k < 9; k++) view.setFloat32(84 + 50 * t + 12 + 4 * k, triangles[9 * t + k], true);
  }
  return new Uint8Array(view.buffer);
}

test('fromStl streams a binary file from a view at any offset as from its own buffer', () => {
  // 200 × 100 squares of two triangles: 40,000 records, more than one piece of the buffer the
  // engine copies a binary file through (16,384 records).
  const [n, m] = [200, 100];
  const tris = [];
  for (let j = 0; j < m; j++) {
    for (let i = 0; i < n; i++) {
      const [a, b, c, d] = [[i, j, 0], [i + 1, j, 0], [i + 1, j + 1, 0], [i, j + 1, 0]];
      tris.push(...a, ...b, ...c, ...a, ...c, ...d);
    }
  }
  const bytes = stlOf(tris);
  // The file inside a larger buffer of NaN patterns, seven bytes in, with five of them after.
  const padded = new Uint8Array(bytes.length + 20).fill(0xff);
  padded.set(bytes, 7);
  const own = Mesh.fromStl(bytes);
  const stages = [];
  const inside = Mesh.fromStl(padded.subarray(7, 7 + bytes.length + 5), (stage, f) => stages.push([stage, f]));
  try {
    assert.equal(own.triangleCount, 40000);
    assert.equal(own.vertexCount, (n + 1) * (m + 1));
    assert.deepEqual(inside.positions(), own.positions());
    assert.deepEqual(inside.indices(), own.indices());
    const report = inside.report();
    assert.equal(report.skippedTriangles, 0, 'no record read from the padding');
    assert.equal(report.trailingBytes, 5);
    assert.deepEqual(report.bboxMax, [n, m, 0]);
    const parse = stages.filter(([stage]) => stage === 'parse').map(([, f]) => f);
    assert.equal(parse[0], 0);
    assert.equal(parse.at(-1), 1);
    assert.ok(parse.every((f, k) => k === 0 || f >= parse[k - 1]), 'parse progress only grows');
  } finally {
    own.free();
    inside.free();
  }
});

/**
 * The draw buffers as the worker built them in JavaScript before the engine did: triangles
 * grouped by patch (counting sort, file order within a patch, dropped ones last), corners
 * expanded through the indices, a box per group and the sphere about the boxes' centre.
 */
function displayInJs(mesh, seg) {
  const positions = mesh.positions();
  const indices = mesh.indices();
  const n = indices.length / 3;
  const patchCount = seg ? seg.patchCount : 0;
  const patchOf = seg ? seg.patchOf() : null;
  const bucketOf = (t) => (patchOf && patchOf[t] >= 0 ? patchOf[t] : patchCount);
  const ranges = new Uint32Array(2 * (patchCount + 1));
  for (let t = 0; t < n; t++) ranges[2 * bucketOf(t) + 1]++;
  const cursor = new Uint32Array(patchCount + 1);
  for (let b = 0, start = 0; b <= patchCount; b++) {
    ranges[2 * b] = start;
    cursor[b] = start;
    start += ranges[2 * b + 1];
  }
  const out = new Float32Array(9 * n);
  const boxes = new Float32Array(6 * (patchCount + 1));
  for (let b = 0; b <= patchCount; b++) boxes.set([Infinity, Infinity, Infinity, -Infinity, -Infinity, -Infinity], 6 * b);
  for (let t = 0; t < n; t++) {
    const b = bucketOf(t);
    let o = 9 * cursor[b]++;
    for (let k = 0; k < 3; k++) {
      const v = 3 * indices[3 * t + k];
      for (let i = 0; i < 3; i++) {
        const x = positions[v + i];
        out[o++] = x;
        boxes[6 * b + i] = Math.min(boxes[6 * b + i], x);
        boxes[6 * b + 3 + i] = Math.max(boxes[6 * b + 3 + i], x);
      }
    }
  }
  const min = [0, 1, 2].map((i) => Math.min(...Array.from({ length: patchCount + 1 }, (_, b) => boxes[6 * b + i])));
  const max = [0, 1, 2].map((i) => Math.max(...Array.from({ length: patchCount + 1 }, (_, b) => boxes[6 * b + 3 + i])));
  const c = [0, 1, 2].map((i) => (min[i] + max[i]) / 2);
  let r2 = 0;
  for (let v = 0; v < positions.length; v += 3) {
    r2 = Math.max(r2, (positions[v] - c[0]) ** 2 + (positions[v + 1] - c[1]) ** 2 + (positions[v + 2] - c[2]) ** 2);
  }
  return { positions: out, ranges, boxes, sphere: [...c, Math.sqrt(r2)] };
}

test('displayBuffers: the faces grouped by patch in indexed chunks, as JavaScript would group them', () => {
  // A real model (patches and dropped faces) and a cap of several chunks (207,600 faces).
  for (const [name, bytes] of [['wing-body', model('wingbody_79868_flow360.stl')], ['cap', capStl(260, 400, 1, 1000)]]) {
    const mesh = Mesh.fromStl(bytes);
    const seg = mesh.segment(paper);
    try {
      for (const [label, owner] of [['segmented', seg], ['whole', mesh]]) {
        const what = `${name} ${label}`;
        const fractions = [];
        const got = owner.displayBuffers((stage, f) => { assert.equal(stage, 'display'); fractions.push(f); });
        const want = displayInJs(mesh, owner === seg ? seg : null);
        assert.ok(got.positions instanceof Float32Array && got.indices instanceof Uint16Array && got.chunks instanceof Uint32Array);
        assert.deepEqual(got.ranges, want.ranges, `${what}: ranges`);
        assert.deepEqual(got.boxes, want.boxes, `${what}: boxes`);
        assert.deepEqual(got.sphere, want.sphere, `${what}: sphere`);
        // The chunks follow each other, within their limits.
        const vertices = got.positions.length / 3;
        let [face, vertex] = [0, 0];
        for (let c = 0; c < got.chunks.length; c += 4) {
          const [first, faces, firstVertex, count] = got.chunks.subarray(c, c + 4);
          assert.deepEqual([first, firstVertex], [face, vertex], `${what}: chunk ${c / 4}`);
          assert.ok(faces >= 1 && faces <= 2 ** 17 && count <= 2 ** 16);
          // Each triangle's corners through its chunk's indices: the JavaScript expansion,
          // and each of its vertices is of its triangle's group.
          for (let t = first; t < first + faces; t++) {
            for (let k = 0; k < 3; k++) {
              const local = got.indices[3 * t + k];
              assert.ok(local < count);
              for (let i = 0; i < 3; i++) {
                if (got.positions[3 * (firstVertex + local) + i] !== want.positions[9 * t + 3 * k + i]) {
                  assert.fail(`${what}: triangle ${t} corner ${k}`);
                }
              }
            }
          }
          face += faces;
          vertex += count;
        }
        assert.deepEqual([face, vertex], [want.positions.length / 9, vertices]);
        if (name === 'cap') assert.ok(got.chunks.length / 4 > 1, 'the cap takes several chunks');
        // The runs give each vertex its triangle's group.
        const groupOf = new Int32Array(vertices).fill(-1);
        for (let r = 0; r < got.runs.length; r += 2) {
          groupOf.fill(got.runs[r + 1], got.runs[r], r + 2 < got.runs.length ? got.runs[r + 2] : vertices);
        }
        for (let g = 0; g < got.ranges.length / 2; g++) {
          for (let t = got.ranges[2 * g]; t < got.ranges[2 * g] + got.ranges[2 * g + 1]; t++) {
            const c = 4 * (got.chunks.findLastIndex((x, i) => i % 4 === 0 && x <= t) / 4);
            for (let k = 0; k < 3; k++) {
              if (groupOf[got.chunks[c + 2] + got.indices[3 * t + k]] !== g) assert.fail(`${what}: vertex group of triangle ${t}`);
            }
          }
        }
        assert.equal(fractions[0], 0);
        assert.equal(fractions.at(-1), 1);
        assert.ok(fractions.every((f, i) => i === 0 || f > fractions[i - 1]), 'progress grows');
      }
      // The last group holds exactly the dropped faces (the wing-body has some).
      const dropped = seg.patchOf().filter((p) => p < 0).length;
      assert.equal(seg.displayBuffers().ranges.at(-1), dropped);
      if (name === 'wing-body') assert.ok(seg.patchCount > 1 && dropped > 0);
    } finally {
      seg.free();
      mesh.free();
    }
  }
});

test('StlReader: a file pushed piece by piece reads as fromStl reads it whole', () => {
  const same = (a, b, what) => {
    assert.deepEqual(a.report(), b.report(), what);
    assert.deepEqual(a.positions(), b.positions(), what);
    assert.deepEqual(a.indices(), b.indices(), what);
  };
  // Binary (a real model, and a file whose head reads like text) and ASCII, in pieces of
  // 1 byte, an odd size, and one piece; pieces given as views into larger buffers and as
  // ArrayBuffers.
  const headed = new Uint8Array(capStl(4, 8, 1, 10));
  headed.set(new TextEncoder().encode('solid but binary'));
  for (const [name, bytes] of [['wing-body', model('wingbody_79868_flow360.stl')], ['headed', headed],
    ['ascii', model('bwb_4464_pygeo_ascii.stl')]]) {
    const whole = Mesh.fromStl(bytes);
    for (const piece of name === 'wing-body' ? [65_537, bytes.length] : [1, 4097, bytes.length]) {
      const stages = new Set();
      const reader = new StlReader(bytes.length, (stage) => stages.add(stage));
      for (let at = 0; at < bytes.length; at += piece) {
        const view = bytes.subarray(at, Math.min(at + piece, bytes.length));
        if ((at / piece) % 2) reader.push(new Uint8Array(view).buffer);
        else reader.push(view);
      }
      assert.equal(reader.received, bytes.length);
      const mesh = reader.finish();
      same(mesh, whole, `${name}, ${piece} a piece`);
      assert.ok(stages.has('parse') && stages.has('adjacency'), [...stages].join());
      mesh.free();
      reader.free();
      assert.throws(() => reader.push(bytes), /StlReader was freed/);
    }
    whole.free();
  }
  // Too many bytes, too few, and a used-up reader: Errors naming them; the module goes on.
  const cube = fixture('cube_binary.stl');
  const reader = new StlReader(cube.length - 1);
  assert.throws(() => reader.push(cube), /bytes changed while they were read: 684 bytes came for a file of 683/);
  assert.throws(() => reader.push(cube.subarray(0, 10)), /used up/);
  const short = new StlReader(cube.length);
  short.push(cube.subarray(0, 100));
  assert.throws(() => short.finish(), /100 bytes came for a file of 684/);
  assert.throws(() => short.finish(), /used up/);
  for (const bad of [-1, 0.5, NaN, '684', 2 ** 31]) {
    assert.throws(() => new StlReader(bad), /byteLength must be a whole number from 0 to 2147483647/);
  }
  assert.throws(() => new StlReader(684).push([1, 2, 3]), /must be a Uint8Array or an ArrayBuffer/);
  assert.throws(() => new StlReader(0).finish(), /the file is empty/);
  const ok = new StlReader(cube.length);
  ok.push(cube);
  assert.equal(ok.finish().triangleCount, 12);
});

test('raycast: the first face along a ray, passing through hidden patches', () => {
  // Two 10 × 10 squares, at z = 0 and z = 2 (two triangles each, not connected).
  const square = (z) => [0, 0, z, 10, 0, z, 10, 10, z, 0, 0, z, 10, 10, z, 0, 10, z];
  const mesh = Mesh.fromStl(stlOf([...square(0), ...square(2)]));
  const origin = [3, 6, 5];
  const down = new Float64Array([0, 0, -4]); // not unit: distances are along the unit direction
  const top = mesh.raycast(origin, down);
  assert.deepEqual(top.point, [3, 6, 2]);
  assert.equal(top.distance, 3);
  assert.ok(top.face === 2 || top.face === 3, `face ${top.face} is on the upper square`);
  assert.equal('patch' in top, false);
  assert.equal(mesh.raycast(origin, [0, 0, 1]), null, 'nothing above');
  assert.equal(mesh.raycast([20, 20, 5], down), null, 'beside the squares');

  const seg = mesh.segment({ angleThreshold: 0.1, minAreaRatio: 0 });
  assert.equal(seg.patchCount, 2);
  const patchOf = seg.patchOf();
  const upper = patchOf[top.face];
  const lower = patchOf[0];
  assert.notEqual(upper, lower);
  assert.deepEqual(seg.raycast(origin, down), { ...top, patch: upper });
  const through = seg.raycast(origin, down, [upper]);
  assert.deepEqual([through.point, through.distance, through.patch], [[3, 6, 0], 5, lower]);
  assert.ok(through.face === 0 || through.face === 1);
  assert.equal(seg.raycast(origin, down, [lower, upper, -1]), null);
  assert.deepEqual(seg.raycast(origin, down, []), seg.raycast(origin, down, null));

  // Bad rays and hidden lists are refused by name; the objects keep working.
  for (const [call, message] of [
    [() => mesh.raycast([0, 0], down), /^origin must be three numbers \[x, y, z\], got an array$/],
    [() => mesh.raycast('0,0,0', down), /^origin must be three numbers \[x, y, z\], got the string "0,0,0"$/],
    [() => mesh.raycast([0, NaN, 0], down), /^origin\[1\] must be a finite number, got NaN$/],
    [() => mesh.raycast(origin, [0, 0, 0]), /^direction must be a non-zero vector of finite length, got \[0, 0, 0\]$/],
    [() => mesh.raycast(origin, [1e308, 1e308, 0]), /^direction must be a non-zero vector of finite length/],
    [() => mesh.raycast(origin), /^direction must be three numbers \[x, y, z\], got undefined$/],
    [() => mesh.raycast(origin, [0, '1', 0]), /^direction\[1\] must be a number, got the string "1"$/],
    [() => seg.raycast(origin, down, [2]), /^hidden\[0\] must be a whole number from -1 to 1, got 2$/],
    [() => seg.raycast(origin, down, [0, 0.5]), /^hidden\[1\] must be a whole number from -1 to 1, got 0\.5$/],
    [() => seg.raycast(origin, down, 'all'), /^hidden must be a Float64Array or an array of numbers, got the string "all"$/],
  ]) {
    assert.throws(call, (e) => e instanceof Error && message.test(e.message), String(message));
  }
  assert.equal(mesh.raycast(origin, down).distance, 3);
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
