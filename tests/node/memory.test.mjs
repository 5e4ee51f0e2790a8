// reserveMemory and the Paths tool's reservation for its first distance (www/worker/warm-up.js),
// in a process of their own: what the engine's memory grows by depends on what ran before.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
const pkg = join(root, 'dist', 'pkg');
const wasm = await import(join(pkg, 'skinpath.js'));
wasm.initSync({ module: readFileSync(join(pkg, 'skinpath_bg.wasm')) });
const { Mesh, reserveMemory, wasmMemoryBytes } = wasm;
const { capStl, reserveFirstDistance, warmUp } = await import(join(root, 'dist', 'worker', 'warm-up.js'));

test('the memory reserved as the Paths tool asks covers its first distance on the model', () => {
  // A cap of R 1000 mm, half-angle 1 rad, about 200k triangles, opened as in the page.
  const mesh = Mesh.fromStl(capStl(160, 640, 1, 1000));
  try {
    warmUp(Mesh);
    const before = wasmMemoryBytes();
    assert.equal(reserveFirstDistance(reserveMemory, mesh.triangleCount), true);
    const reserved = wasmMemoryBytes();
    // Grown: opening the model and the warm-up left less than that free.
    assert.ok(reserved > before, `${before} → ${reserved} bytes`);
    for (const source of [{ boundaryOf: 'mesh' }, { plane: { point: [0, 0, 1000 * Math.cos(0.5)], normal: [0, 0, 1] } }]) {
      const field = mesh.geodesicDistance(source, { method: 'accurate' });
      assert.equal(field.method, 'accurate');
      field.free();
      assert.equal(wasmMemoryBytes(), reserved, `the distance from ${JSON.stringify(source)} grew the memory`);
    }
  } finally {
    mesh.free();
  }
});

test('reserveMemory refuses what is not a byte count, and the engine keeps working', () => {
  for (const bad of [NaN, -1, Infinity, 5e9, 'a lot', '1000', true, null]) {
    assert.throws(() => reserveMemory(bad), (e) => e instanceof Error && /reserveMemory: bytes must be a number from 0 to/.test(e.message),
      `reserveMemory(${String(bad)})`);
  }
  assert.equal(reserveMemory(0), true);
  const at = wasmMemoryBytes();
  assert.equal(reserveMemory(at + 2 ** 20), true);
  assert.ok(wasmMemoryBytes() > at);
  const mesh = Mesh.fromStl(capStl(4, 16, 1, 1));
  assert.ok(mesh.triangleCount > 0);
  mesh.free();
});
