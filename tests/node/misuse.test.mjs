// Misuse of the built wasm package from JavaScript: hostile parameter objects (cycles, deep
// nesting, throwing getters and Proxy traps), wrong types, out-of-range ids, oversize input,
// use after free() and re-entrant progress callbacks. Every call must return or throw an
// `Error` whose message names the problem, and the module must keep working afterwards.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const pkg = join(root, 'dist', 'pkg');
const wasm = await import(join(pkg, 'skinpath.js'));
wasm.initSync({ module: readFileSync(join(pkg, 'skinpath_bg.wasm')) });
const { Mesh, Segmentation, DistanceField, ToolPath, deriveThreshold, wasmMemoryBytes } = wasm;
const cube = readFileSync(join(root, 'tests', 'fixtures', 'cube_binary.stl'));
const paper = { angleThreshold: 0.35, thetaMax: 1, minAreaRatio: 0.1 };

// What wasm-bindgen or a trap says when the boundary failed rather than the input.
const BROKEN = /unreachable|RuntimeError|memory access|null pointer|recursive use|ownership of Rust value|JsValue\(|Reflect\.|invalid type/;

/** Calls `f`, which must throw an Error whose message matches `pattern` and no internal one. */
function refuses(f, pattern) {
  let thrown = null;
  try {
    f();
  } catch (e) {
    thrown = e;
  }
  assert.ok(thrown !== null, `accepted, expected ${pattern}`);
  assert.ok(thrown instanceof Error, `threw a non-Error: ${String(thrown)}`);
  assert.match(thrown.message, pattern);
  assert.doesNotMatch(thrown.message, BROKEN);
  return thrown.message;
}

/** The module still works: a cube segments into 6 patches and frees cleanly. */
function stillWorks() {
  const mesh = Mesh.fromStl(cube);
  const seg = mesh.segment(paper);
  assert.equal(seg.patchCount, 6);
  assert.equal(seg.patchStl(5).length, 84 + 50 * 2);
  seg.free();
  mesh.free();
}

test('a cyclic params object is refused by name, not followed', () => {
  const mesh = Mesh.fromStl(cube);
  const p = { ...paper };
  p.self = p;
  refuses(() => mesh.segment(p), /^unknown segmentation parameter 'self'$/);
  const q = { angleThreshold: 0.35 };
  q.spray = q;
  refuses(() => mesh.segment(q), /^unknown segmentation parameter 'spray\.angleThreshold'$/);
  refuses(() => deriveThreshold(q), /^unknown segmentation parameter 'spray\.angleThreshold'$/);
  assert.equal(mesh.segment(paper).patchCount, 6);
  mesh.free();
  stillWorks();
});

test('params nested 5,000 and 100,000 deep are refused without recursion', () => {
  const mesh = Mesh.fromStl(cube);
  for (const depth of [5000, 100000]) {
    let deep = { meanThickness: 100, allowedDeviation: 6, minThickness: 97 };
    for (let i = 0; i < depth; i++) deep = { spray: deep };
    refuses(() => mesh.segment(deep), /^unknown segmentation parameter 'spray\.spray'$/);
    refuses(() => mesh.segment({ ...paper, extra: deep }), /^unknown segmentation parameter 'extra'$/);
    refuses(() => deriveThreshold({ grind: deep }), /^unknown segmentation parameter 'grind\.spray'$/);
  }
  assert.equal(mesh.segment(paper).patchCount, 6);
  mesh.free();
  stillWorks();
});

test('a throwing getter or Proxy trap leaves no borrow or leak behind', () => {
  const mesh = Mesh.fromStl(cube);
  const getter = {
    ...paper,
    get thetaMax() {
      throw new Error('boom');
    },
  };
  refuses(() => mesh.segment(getter), /^reading segmentation parameter 'thetaMax' threw: boom$/);
  const nestedGetter = { spray: { meanThickness: 100, allowedDeviation: 6, get minThickness() { throw 'a string'; } } };
  refuses(() => deriveThreshold(nestedGetter), /^reading segmentation parameter 'spray\.minThickness' threw: a string$/);
  const getTrap = new Proxy({}, { get() { throw new TypeError('get trap'); } });
  refuses(() => mesh.segment(getTrap), /^reading segmentation parameter 'angleThreshold' threw: get trap$/);
  const keysTrap = new Proxy({ ...paper }, { ownKeys() { throw new RangeError('keys trap'); } });
  refuses(() => mesh.segment(keysTrap), /^listing the keys of segmentation parameters threw: keys trap$/);
  const { proxy: revoked, revoke } = Proxy.revocable({}, {});
  revoke();
  refuses(() => mesh.segment(revoked), /^listing the keys of segmentation parameters threw: .*revoked/);
  const overflow = { get angleThreshold() { return overflow.angleThreshold; } };
  refuses(() => mesh.segment(overflow), /^reading segmentation parameter 'angleThreshold' threw: Maximum call stack size exceeded$/);
  const before = wasmMemoryBytes();
  for (let i = 0; i < 2000; i++) {
    assert.throws(() => mesh.segment(i % 2 ? getter : getTrap), Error);
  }
  assert.equal(wasmMemoryBytes(), before, 'throwing getters must not grow memory');
  // The same mesh still works and frees: no borrow was left taken.
  assert.equal(mesh.segment(paper).patchCount, 6);
  mesh.free();
  stillWorks();
});

test('params that are not an object are named', () => {
  const mesh = Mesh.fromStl(cube);
  const cases = [
    [null, 'null'], [undefined, 'undefined'], ['0.35', 'the string "0.35"'], [0.35, 'the number 0.35'],
    [[0.35], 'an array'], [() => paper, 'a function'], [true, 'true'], [10n, 'a BigInt'], [Symbol('p'), 'a symbol'],
    ['x'.repeat(1000), `the string "${'x'.repeat(40)}"…`],
  ];
  for (const [value, described] of cases) {
    const escaped = described.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
    refuses(() => mesh.segment(value), new RegExp(`^segmentation parameters must be an object, got ${escaped}$`));
    refuses(() => deriveThreshold(value), new RegExp(`^segmentation parameters must be an object, got ${escaped}$`));
  }
  mesh.free();
});

test('wrong-typed, missing, unknown and huge fields are named with their path', () => {
  const cases = [
    [{ angleThreshold: '0.35' }, /^angleThreshold must be a number, got the string "0\.35"$/],
    [{ ...paper, thetaMax: '0.35' }, /^thetaMax must be a number, got the string "0\.35"$/],
    [{ ...paper, thetaMax: null }, /^thetaMax must be a number, got null$/],
    [{ ...paper, minAreaRatio: {} }, /^minAreaRatio must be a number, got an object$/],
    [{ ...paper, minAreaRatio: new Number(0.1) }, /^minAreaRatio must be a number, got a Number$/],
    [{ spray: 5 }, /^spray must be an object, got the number 5$/],
    [{ grind: [1, 2, 3] }, /^grind must be an object, got an array$/],
    [{ spray: { meanThickness: 100, allowedDeviation: true, minThickness: 97 } }, /^spray\.allowedDeviation must be a number, got true$/],
    [{ spray: { meanThickness: 100, allowedDeviation: 6 } }, /^segmentation parameter 'spray\.minThickness' is missing$/],
    [{ ...paper, seedRule: 'random' }, /^seedRule must be one of "lowestIndex", "flattest", "largestArea", got the string "random"$/],
    [{ ...paper, seedRule: 2 }, /^seedRule must be one of .*, got the number 2$/],
    [{ ...paper, thetaMaks: 1 }, /^unknown segmentation parameter 'thetaMaks'$/],
    [{ spray: { meanThickness: 100, allowedDeviation: 6, minThickness: 97, typo: 1 } }, /^unknown segmentation parameter 'spray\.typo'$/],
    [{ ...paper, thetaMax: 1.7e308 }, /^thetaMax must be in \(0, π\] radians, got 1\.7e308$/],
    [{ ...paper, thetaMax: -Number.MAX_VALUE }, /^thetaMax must be in \(0, π\] radians, got -1\.7976931348623157e308$/],
    [{ ...paper, thetaMax: Infinity }, /^thetaMax must be a finite number, got Infinity$/],
    [{ ...paper, thetaMax: NaN }, /^thetaMax must be a finite number, got NaN$/],
    [{ curvatureThreshold: -1e-300 }, /^curvatureThreshold must be greater than 0, got -1e-300$/],
    [{}, /^give exactly one of angleThreshold, curvatureThreshold, spray or grind \(got none\)$/],
  ];
  const mesh = Mesh.fromStl(cube);
  for (const [params, pattern] of cases) {
    const message = refuses(() => mesh.segment(params), pattern);
    assert.doesNotMatch(message, /\d{20}/, 'a long number was echoed back');
    refuses(() => deriveThreshold(params), pattern);
  }
  // Symbol keys and inherited known keys are fine; undefined means "not given".
  const withSymbol = { ...paper, [Symbol('tag')]: 1, minAreaRatio: undefined };
  assert.equal(mesh.segment(withSymbol).patchCount, 6);
  assert.equal(mesh.segment(Object.create(paper)).patchCount, 6);
  mesh.free();
});

test('patchStl and patchFaces refuse every id that is not a whole number in range, naming it', () => {
  const mesh = Mesh.fromStl(cube);
  const seg = mesh.segment(paper);
  const none = mesh.segment({ ...paper, minAreaRatio: 0.99 });
  assert.equal(none.patchCount, 0);
  // patchFaces took a u32 once: -1, 0.5, NaN and '1' were turned into ids without a word.
  for (const method of ['patchStl', 'patchFaces']) {
    const call = (s, id) => s[method](id);
    const notWhole = /^patch id must be a whole number from 0 to 5, got /;
    const cases = [
      [NaN, /got NaN$/], [0.5, /got 0\.5$/], ['abc', /got the string "abc"$/], ['0', /got the string "0"$/],
      [undefined, /got undefined$/], [null, /got null$/], [Infinity, /got Infinity$/], [[0], /got an array$/],
    ];
    for (const [id, tail] of cases) {
      const message = refuses(() => call(seg, id), notWhole);
      assert.match(message, tail);
    }
    refuses(() => call(seg, 2 ** 32), /^no patch 4294967296: this segmentation has 6 patches, ids 0 to 5$/);
    refuses(() => call(seg, -1), /^no patch -1: this segmentation has 6 patches, ids 0 to 5$/);
    refuses(() => call(seg, 6), /^no patch 6: this segmentation has 6 patches, ids 0 to 5$/);
    refuses(() => call(seg, 1e300), /^no patch 1e300: /);
    refuses(() => call(none, 0), /^no patch 0: this segmentation has no patches$/);
    refuses(() => call(none, 'x'), /^no patch the string "x": this segmentation has no patches$/);
  }
  for (let id = 0; id < 6; id++) {
    assert.equal(seg.patchStl(id).length, 84 + 50 * 2);
    assert.equal(seg.patchFaces(id).length, 2);
  }
  none.free();
  seg.free();
  mesh.free();
});

test('fromStl takes a Uint8Array or an ArrayBuffer and refuses other types and 2 GiB', () => {
  const copy = new Uint8Array(cube).buffer;
  assert.equal(Mesh.fromStl(copy).triangleCount, 12, 'an ArrayBuffer is read');
  assert.equal(Mesh.fromStl(new Uint8Array(copy, 0, cube.length)).triangleCount, 12);
  const cases = [
    [[...cube], 'an array'], ['solid x', 'the string "solid x"'], [null, 'null'], [undefined, 'undefined'],
    [new Float32Array(4), 'a Float32Array'], [new Blob([cube]), 'a Blob'], [new DataView(copy), 'a DataView'],
  ];
  for (const [value, described] of cases) {
    refuses(() => Mesh.fromStl(value), new RegExp(`^the STL file must be a Uint8Array or an ArrayBuffer, got ${described}$`));
  }
  const detached = new Uint8Array(cube).buffer;
  const view = new Uint8Array(detached);
  structuredClone(detached, { transfer: [detached] });
  refuses(() => Mesh.fromStl(detached), /^the file is empty$/);
  refuses(() => Mesh.fromStl(view), /^the file is empty$/);
  refuses(() => Mesh.fromStl(cube, 5), /^onProgress must be a function, got the number 5$/);
  refuses(() => Mesh.fromStl(cube).segment(paper, 'progress'), /^onProgress must be a function, got the string "progress"$/);
  let huge = null;
  try {
    huge = new Uint8Array(2 ** 31); // zero pages: Node reserves but does not touch them
  } catch {
    // Not enough address space here: the check below cannot run.
  }
  if (huge) {
    refuses(() => Mesh.fromStl(huge), /^the file is 2147483648 bytes; the engine can hold at most 2147483647 bytes/);
    refuses(() => Mesh.fromStl(huge.buffer), /^the file is 2147483648 bytes; /);
    huge = null;
  }
  stillWorks();
});

test('a progress callback that detaches the file while it is read gets an Error, not a trap', () => {
  // 40,000 triangles: the engine copies a binary file in pieces of 16,384 records and calls
  // onProgress between them, so the buffer can go while it is read.
  const count = 40000;
  const bytes = new Uint8Array(84 + 50 * count);
  const view = new DataView(bytes.buffer);
  view.setUint32(80, count, true);
  for (let t = 0; t < count; t++) {
    const [x, y] = [t % 200, Math.floor(t / 200)];
    const corners = [x, y, 0, x + 1, y, 0, x, y + 1, 0];
    corners.forEach((c, k) => view.setFloat32(84 + 50 * t + 12 + 4 * k, c, true));
  }
  const detach = () => structuredClone(bytes.buffer, { transfer: [bytes.buffer] });
  refuses(() => Mesh.fromStl(bytes, detach), /^the STL file's bytes changed while they were read: its buffer was detached or resized/);
  stillWorks();
});

test('use after free() says which object was freed, for every class and member', () => {
  const mesh = Mesh.fromStl(cube);
  const seg = mesh.segment(paper);
  const field = mesh.geodesicDistance({ vertices: [0] });
  const path = field.toolPath(field.maxDistance / 3);
  const classes = [[Mesh, mesh, /^this Mesh was freed \(free\(\) was called\); load the file again$/],
    [Segmentation, seg, /^this Segmentation was freed \(free\(\) was called\); segment the mesh again$/],
    [DistanceField, field, /^this DistanceField was freed \(free\(\) was called\); compute the distance again$/],
    [ToolPath, path, /^this ToolPath was freed \(free\(\) was called\); build the tool path again$/]];
  mesh.free();
  assert.equal(seg.patchStl(0).length, 184, 'a segmentation outlives its freed mesh');
  assert.ok(field.isoPaths(field.maxDistance / 3).length > 0, 'a distance field outlives its freed mesh');
  seg.free();
  field.free();
  path.free();
  for (const [cls, object, freed] of classes) {
    object.free(); // a second free() does nothing
    const members = Object.getOwnPropertyNames(cls.prototype).filter((k) => k !== 'constructor' && k !== 'free' && !k.startsWith('__'));
    assert.ok(members.length >= 5, `${cls.name} has members`);
    for (const key of members) {
      const d = Object.getOwnPropertyDescriptor(cls.prototype, key);
      refuses(() => (d.get ? object[key] : object[key](paper, undefined)), freed);
    }
  }
  stillWorks();
});

test('an object made with new of a class the engine makes says how to make one', () => {
  const made = [[Mesh, /^this Mesh was made with new Mesh\(\), which gives an empty object: use Mesh\.fromStl\(bytes\)/],
    [Segmentation, /^this Segmentation was made with new Segmentation\(\), which gives an empty object: use mesh\.segment\(params\)$/],
    [DistanceField, /use mesh\.geodesicDistance\(source, options\)$/], [ToolPath, /use field\.toolPath\(spacing, options\)$/]];
  for (const [cls, message] of made) {
    const empty = new cls();
    const members = Object.getOwnPropertyNames(cls.prototype).filter((k) => k !== 'constructor' && k !== 'free' && !k.startsWith('__'));
    for (const key of members) {
      const d = Object.getOwnPropertyDescriptor(cls.prototype, key);
      refuses(() => (d.get ? empty[key] : empty[key](paper, undefined)), message);
    }
    empty.free(); // nothing to free
  }
  stillWorks();
});

test('a progress callback that throws or re-enters does not break the call or the mesh', () => {
  let calls = 0;
  const thrower = () => {
    calls++;
    throw new Error('progress display failed');
  };
  const mesh = Mesh.fromStl(cube, thrower);
  assert.ok(calls > 0);
  assert.equal(mesh.segment(paper, thrower).patchCount, 6);
  // Re-entry: reading and segmenting the same mesh from inside its own segment(), once.
  let inner = null;
  let triangles = 0;
  const reenter = () => {
    triangles = mesh.triangleCount;
    if (inner === null) {
      inner = false;
      inner = mesh.segment(paper, reenter);
    }
  };
  const outer = mesh.segment(paper, reenter);
  assert.equal(outer.patchCount, 6);
  assert.equal(inner.patchCount, 6);
  assert.equal(triangles, 12);
  // Unbounded re-entry is cut off with an Error inside the callback, not a stack overflow.
  const errors = [];
  const recurse = () => {
    try {
      mesh.segment(paper, recurse).free();
    } catch (e) {
      errors.push(e);
    }
  };
  mesh.segment(paper, recurse).free();
  assert.ok(errors.length > 0);
  for (const e of errors) {
    assert.ok(e instanceof Error);
    assert.match(e.message, /^Mesh\.segment\(\) was called from an onProgress callback 4 calls deep; call it after the outer call returns$/);
  }
  const fromInside = [];
  Mesh.fromStl(cube, function again() {
    try {
      Mesh.fromStl(cube, again).free();
    } catch (e) {
      fromInside.push(e.message);
    }
  }).free();
  assert.match(fromInside[0], /^Mesh\.fromStl\(\) was called from an onProgress callback 4 calls deep/);
  // free() from inside: the mesh is freed once segment() returns, and the result is whole.
  let freedInside = false;
  const seg = mesh.segment(paper, () => {
    if (!freedInside) {
      freedInside = true;
      mesh.free();
      refuses(() => mesh.triangleCount, /^this Mesh was freed/);
    }
  });
  assert.ok(freedInside);
  assert.equal(seg.patchCount, 6);
  assert.equal(seg.patchStl(0).length, 184);
  refuses(() => mesh.segment(paper), /^this Mesh was freed/);
  for (const s of [seg, inner, outer]) s.free();
  stillWorks();
});

// A fixed-seed generator of hostile inputs: params from a grammar of keys, types and values,
// and random calls on live and freed objects.
function mulberry32(seed) {
  return () => {
    seed = (seed + 0x6d2b79f5) | 0;
    let t = Math.imul(seed ^ (seed >>> 15), 1 | seed);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

const FUZZ_CASES = 4000;

test(`fuzz: ${FUZZ_CASES} random params and calls return or throw an Error, and the module survives`, () => {
  const random = mulberry32(20260601);
  const pick = (list) => list[Math.floor(random() * list.length)];
  const TOP = ['angleThreshold', 'curvatureThreshold', 'spray', 'grind', 'thetaMax', 'minAreaRatio', 'seedRule', 'thetaMaks', '', '__proto__', 'constructor', '0'];
  const SPRAY = ['meanThickness', 'allowedDeviation', 'minThickness', 'typo'];
  const GRIND = ['indentationDepth', 'minPressureRatio', 'contactWidth', 'typo'];
  // No tiny positive numbers: a thetaMax near 1e-8 is the core's own (separate) problem.
  const NUMBERS = [0, -0, 0.35, 1, 3.14159, Math.PI, 4, -1, 0.5, 0.99, 6, 97, 100, 1e308, -1e308, NaN, Infinity, -Infinity, 2 ** 32, 2 ** 53];
  const value = (depth, keys) => {
    switch (Math.floor(random() * 14)) {
      case 0: return pick(['0.35', '', 'flattest', 'largestArea', 'lowestIndex', 'x'.repeat(300)]);
      case 1: return pick([null, undefined, true, false]);
      case 2: return pick([[], [1, 2], new Float64Array(3)]);
      case 3: return depth < 3 ? object(depth + 1, pick([SPRAY, GRIND, TOP])) : {};
      case 4: {
        let deep = {};
        for (let i = 0, n = Math.floor(random() * 3000); i < n; i++) deep = { spray: deep };
        return deep;
      }
      case 5: return new Proxy(object(depth + 1, keys), pick([{}, { get() { throw new Error('trap'); } }, { ownKeys() { throw 1; } }]));
      case 6: return pick([() => 1, Symbol('s'), 1n, new Date(0)]);
      default: return pick(NUMBERS);
    }
  };
  const object = (depth, keys) => {
    const o = {};
    for (let i = 0, n = Math.floor(random() * 5); i < n; i++) {
      const key = pick(keys);
      if (random() < 0.05) {
        Object.defineProperty(o, key, { enumerable: true, get() { throw new Error('getter'); } });
      } else {
        o[key] = key === 'spray' && depth < 2 ? object(depth + 1, SPRAY) : key === 'grind' && depth < 2 ? object(depth + 1, GRIND) : value(depth, keys);
      }
    }
    if (random() < 0.05) o.spray = o;
    return o;
  };
  const params = () => (random() < 0.1 ? value(0, TOP) : object(0, TOP));
  const meshes = [Mesh.fromStl(cube)];
  const segs = [meshes[0].segment(paper)];
  let returned = 0;
  let thrown = 0;
  for (let i = 0; i < FUZZ_CASES; i++) {
    const action = Math.floor(random() * 8);
    const call = () => {
      switch (action) {
        case 0: return deriveThreshold(params());
        case 1: {
          const seg = pick(meshes).segment(params(), random() < 0.2 ? pick([() => { throw new Error('p'); }, 7]) : undefined);
          segs.push(seg);
          return seg;
        }
        case 2: return pick(segs).patchStl(random() < 0.5 ? Math.floor(random() * 8) - 1 : value(0, TOP));
        case 3: {
          const m = Mesh.fromStl(random() < 0.7 ? cube : value(0, TOP));
          meshes.push(m);
          return m;
        }
        case 4: return pick(random() < 0.5 ? meshes : segs).free();
        case 5: return pick(segs).patches();
        case 6: return pick(meshes).report();
        default: return pick(segs).borderPatches();
      }
    };
    try {
      call();
      returned++;
    } catch (e) {
      thrown++;
      assert.ok(e instanceof Error, `case ${i}: threw a non-Error ${String(e)}`);
      assert.ok(e.message.length > 0, `case ${i}: an empty message`);
      assert.doesNotMatch(e.message, BROKEN, `case ${i}`);
      assert.doesNotMatch(e.message, /\d{20}/, `case ${i}: a long number was echoed back`);
    }
  }
  assert.ok(returned > FUZZ_CASES / 10 && thrown > FUZZ_CASES / 10, `returned ${returned}, threw ${thrown}`);
  for (const o of [...segs, ...meshes]) o.free();
  stillWorks();
});

test('an argument too many is refused by name for every export, never dropped', () => {
  refuses(() => wasm.correctHoles({}, Mesh.fromStl(cube)),
    /^correctHoles\(\) takes at most 1 argument \(params\), got 2: to project the corrected holes onto a panel, call mesh\.correctHoles\(params\) on the Mesh$/);
  const mesh = Mesh.fromStl(cube);
  const seg = mesh.segment(paper);
  const field = mesh.geodesicDistance({ vertices: [0] });
  const path = field.toolPath(field.maxDistance / 3);
  const plan = mesh.planSpray({ spacing: 0.3, standoff: 0.25, speed: 0.4, flowRate: 2.5e-6, coneAngle: 0.7,
    transitionAngle: 0.35, efficiency: 0.6 });
  refuses(() => mesh.segment(paper, undefined, 1),
    /^Mesh\.segment\(\) takes at most 2 arguments \(params, onProgress\), got 3: the extra ones would be ignored$/);
  refuses(() => Mesh.fromStl(cube, null, {}), /^Mesh\.fromStl\(\) takes at most 2 arguments \(bytes, onProgress\), got 3: /);
  refuses(() => seg.patchStl(0, 1), /^Segmentation\.patchStl\(\) takes at most 1 argument \(id\), got 2: /);
  refuses(() => wasmMemoryBytes(0), /^wasmMemoryBytes\(\) takes no arguments, got 1: /);
  refuses(() => deriveThreshold(paper, paper), /^deriveThreshold\(\) takes at most 1 argument \(params\), got 2: /);
  // Extra arguments that are undefined change nothing and are let through.
  assert.equal(mesh.segment(paper, undefined, undefined).patchCount, 6);
  assert.equal(deriveThreshold(paper, undefined).kind, 'angle');
  // Every exported function, static and method, with one argument more than it declares.
  const functions = Object.entries(wasm).filter(([k, v]) => typeof v === 'function' && !/^[A-Z]/.test(k)
    && k !== 'initSync' && k !== 'default' && k !== 'installPanicHook');
  assert.ok(functions.length >= 6, functions.map(([k]) => k).join());
  for (const [name, f] of functions) {
    refuses(() => f(...Array(f.length).fill(undefined), 0), new RegExp(`^${name}\\(\\) takes `));
  }
  let checked = 0;
  for (const [cls, object] of [[Mesh, mesh], [Segmentation, seg], [DistanceField, field], [ToolPath, path],
    [wasm.SprayPlan, plan]]) {
    for (const [owner, target] of [[cls.prototype, object], [cls, cls]]) {
      for (const key of Object.getOwnPropertyNames(owner)) {
        const d = Object.getOwnPropertyDescriptor(owner, key);
        if (typeof d.value !== 'function' || key === 'constructor' || key === 'free' || key.startsWith('__')) continue;
        refuses(() => target[key](...Array(d.value.length).fill(undefined), 'extra'),
          new RegExp(`^${cls.name}\\.${key}\\(\\) takes (at most ${d.value.length} argument|no arguments)`));
        checked++;
      }
    }
  }
  assert.ok(checked >= 40, `${checked} methods checked`);
  for (const o of [plan, path, field, seg, mesh]) o.free();
  stillWorks();
});

test('every export with a wrong value in any one argument returns or throws an Error, never traps', () => {
  // A wrong type where a string was taken made the generated glue write out of bounds (a
  // RuntimeError, parseHolesCsv(42)); this calls every exported function, method and static
  // method with each of these in each argument it declares, the others undefined.
  const wrong = [42, -1, 0.5, NaN, null, undefined, 'x', '1', {}, [], [1, 'a'], true, 2 ** 40, new Uint8Array(3), 10n];
  const mesh = Mesh.fromStl(cube);
  const seg = mesh.segment(paper);
  const plan = mesh.planSpray({ spacing: 0.5, standoff: 1, speed: 1, flowRate: 1e-3, coneAngle: 0.5, transitionAngle: 0.3,
    efficiency: 0.6, optimiseSpeed: false }, seg.patchFaces(0));
  const field = mesh.geodesicDistance({ vertices: [0] });
  const path = field.toolPath(field.maxDistance / 3);
  const targets = [];
  for (const [name, f] of Object.entries(wasm)) {
    if (typeof f !== 'function' || name === 'initSync' || name === 'default') continue;
    if (/^[A-Z]/.test(name)) {
      for (const key of Object.getOwnPropertyNames(f)) {
        if (typeof f[key] === 'function' && !key.startsWith('__')) targets.push([`${name}.${key}`, f[key].length, (...a) => f[key](...a)]);
      }
    } else {
      targets.push([name, f.length, f]);
    }
  }
  for (const [label, object] of [['mesh', mesh], ['seg', seg], ['plan', plan], ['field', field], ['path', path]]) {
    const proto = Object.getPrototypeOf(object);
    for (const key of Object.getOwnPropertyNames(proto)) {
      const d = Object.getOwnPropertyDescriptor(proto, key);
      if (key === 'constructor' || key === 'free' || key.startsWith('__') || typeof d.value !== 'function') continue;
      targets.push([`${label}.${key}`, d.value.length, (...a) => object[key](...a)]);
    }
  }
  assert.ok(targets.length > 50, `${targets.length} exports probed`);
  let calls = 0;
  for (const [label, arity, call] of targets) {
    for (let at = 0; at < Math.max(arity, 1); at++) {
      for (const value of wrong) {
        const args = new Array(Math.max(arity, 1)).fill(undefined);
        args[at] = value;
        calls++;
        try {
          const out = call(...args);
          if (out && typeof out.free === 'function') out.free();
        } catch (e) {
          assert.ok(e instanceof Error && !(e instanceof WebAssembly.RuntimeError), `${label}: argument ${at} = ${String(value)} threw ${e?.constructor?.name}: ${e?.message ?? e}`);
          assert.doesNotMatch(e.message, BROKEN, `${label}: argument ${at} = ${String(value)}`);
        }
      }
    }
  }
  assert.ok(calls > 1000, `${calls} calls`);
  for (const object of [path, field, plan, seg, mesh]) object.free();
  stillWorks();
});
