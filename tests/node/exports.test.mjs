// The robot-program export options from JavaScript (ExportOptions): every key reaches the
// programs, defaults say what the cell must set up, and bad values are refused naming the key.
// Uses the paper's drilling example (Mesh.drillingProgram) and a ToolPath of geodesic passes.
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

function withExample(fn) {
  const ex = wasm.drillPaperExample();
  const mesh = Mesh.fromStl(ex.stl);
  try {
    fn((format, options) => mesh.drillingProgram({ references: ex.references, holes: ex.holes }, undefined, format, options));
  } finally {
    mesh.free();
  }
}

test('defaults: a joint move first, ConfL off, exact stops at the drilled depths, A/C within ±180°', () => {
  withExample((program) => {
    const [rapid] = program('rapid', { name: 'drill_a' });
    const lines = rapid.split('\n');
    const first = (re) => lines.findIndex((l) => re.test(l));
    assert.ok(first(/^\s*ConfL\\Off;/) >= 0 && first(/^\s*ConfL\\Off;/) < first(/^\s*MoveJ /));
    assert.ok(first(/^\s*MoveJ /) < first(/^\s*MoveL /), 'the joint move comes first');
    // 16 holes + approach + retract are exact stops.
    assert.equal((rapid.match(/\bfine,/g) ?? []).length, 16 + 2);
    assert.match(rapid, /doProcess must exist in the I\/O/);
    const krl = program('krl', { name: 'drill_k' }).join('\n');
    const angles = [...krl.matchAll(/A (-?[\d.]+),B (-?[\d.]+),C (-?[\d.]+)\}/g)].map((m) => m.slice(1).map(Number));
    assert.equal(angles.length, 48 + 2);
    assert.ok(angles.every(([a, b, c]) => Math.abs(a) <= 180 && Math.abs(b) <= 90 && Math.abs(c) <= 180));
    assert.equal((krl.match(/^\s*PTP \{/gm) ?? []).length, 1);
  });
});

test('every cell option reaches the programs', () => {
  withExample((program) => {
    const options = {
      name: 'cell_test', approachClearanceMm: 75, rapidTool: 'tGun', rapidWorkObject: 'wPanel', rapidSignal: 'doGun',
      rapidConfigCheck: true, krlOutput: 7, krlTool: 3, krlBase: 5, krlUnwrapAngles: true,
    };
    const [rapid] = program('rapid', options);
    assert.match(rapid, /PERS tooldata tGun :=/);
    assert.match(rapid, /PERS wobjdata wPanel :=/);
    assert.match(rapid, /SetDO doGun,1;/);
    assert.match(rapid, /tGun\\WObj:=wPanel;/);
    assert.match(rapid, /ConfL\\On;/);
    assert.doesNotMatch(rapid, /ConfL\\Off;/);
    assert.match(rapid, /75 mm back along/);
    const krl = program('krl', options).join('\n');
    assert.match(krl, /\$TOOL = TOOL_DATA\[3\]/);
    assert.match(krl, /\$BASE = BASE_DATA\[5\]/);
    assert.match(krl, /DO \$OUT\[7\]=TRUE/);
    assert.match(krl, /unwrapped beyond/);
  });
});

test('bad options and reserved names are refused, naming the key or the clash', () => {
  withExample((program) => {
    const refuses = (options, re) => assert.throws(() => program('rapid', options), re);
    refuses({ approachClearanceMm: 0 }, /approachClearanceMm/);
    refuses({ rapidTool: 'tool0' }, /rapidTool.*tool0.*predefined/);
    refuses({ rapidSignal: 'MOVEL' }, /rapidSignal/);
    refuses({ name: 'v1000' }, /name.*speeddata/);
    refuses({ rapidConfigCheck: 'yes' }, /rapidConfigCheck must be true or false/);
    assert.throws(() => program('krl', { name: 'bas' }), /name.*BAS/);
    assert.throws(() => program('krl', { name: 'Tool_Data' }), /TOOL_DATA/);
    assert.throws(() => program('krl', { krlOutput: 0 }), /krlOutput/);
    assert.throws(() => program('krl', { krlTool: 1.5 }), /krlTool must be a whole number/);
    // The controller's ranges are named wherever a value falls out of them (−1 said "from 0
    // to 4294967295", 17 "in 1..=16").
    for (const [key, max] of [['krlOutput', 4096], ['krlTool', 16], ['krlBase', 32]]) {
      for (const bad of [-1, 0, max + 1]) {
        assert.throws(() => program('krl', { [key]: bad }), new RegExp(`^Error: ${key} must be a whole number from 1 to ${max}, got `));
      }
    }
    assert.throws(() => program('krl', { krlUnwrap: true }), /unknown export option 'krlUnwrap'/);
  });
});
