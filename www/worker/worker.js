// Module worker: the only place (with app/engine.js) that loads the wasm package. It owns the
// live Mesh, so that re-segmenting or planning never re-parses, and dispatches requests to
// the tools' worker modules (worker/segment.js, worker/spray.js, …).
//
// Protocol (app/engine.js is the other side; ids tie replies to requests):
//   page → worker  { id, op, ...payload }        op = 'open', 'pick', 'display' or '<tool>.<name>'
//   worker → page  { type: 'ready' } | { type: 'fatal', message }     once, after wasm init
//                  { id, type: 'progress', stage, fraction }           any number, then
//                  { id, type: 'done', result }                        either this
//                  { id, type: 'error', message, broken }              or this
// Requests run one at a time, in order. Typed arrays in results are transferred, not copied.
// Once a model is open and no request has come for a second, the worker warms the geodesic
// code up (warm-up.js), once: the Paths tool's first distance then runs optimised code.
// `broken` means the wasm instance may be corrupt: the page then replaces this worker. Cancel
// also replaces the worker (a running wasm call cannot be interrupted otherwise).
//
// A tool's worker module exports { ops, onOpen?, onMeshChanged?, meshFree? }
// (meshFree: names of ops that run without a model):
//   ops[name](ctx, message, progress) -> [result, transferList]    handles '<tool>.<name>'
//   onOpen(ctx, params, progress) -> result        runs right after parsing when the page sent
//                                                  params for this tool (segment: segmenting)
//   onMeshChanged(ctx)                             the mesh was replaced: drop derived state
// `ctx` is shared: { mesh, segmentation, welded(), display(progress), describe(error, doing) }.
// Workers ignore the page's import map, hence relative paths.
import init, { Mesh, wasmMemoryBytes } from '../pkg/skinpath.js';
import * as segmentTool from './segment.js';
import * as sprayTool from './spray.js';
import * as drillTool from './drill.js';
import * as pathsTool from './paths.js';
import { patchColorBytes } from '../viewer/palette.js';
import { warmUp } from './warm-up.js';

const TOOLS = { segment: segmentTool, spray: sprayTool, drill: drillTool, paths: pathsTool };

/** Posts progress at most once per whole percent per stage: the core may call back often. */
function progressFor(id) {
  let lastStage = null;
  let lastPercent = -1;
  return (stage, fraction) => {
    const percent = Math.floor(Math.min(Math.max(fraction, 0), 1) * 100);
    if (stage === lastStage && percent === lastPercent) return;
    lastStage = stage;
    lastPercent = percent;
    postMessage({ id, type: 'progress', stage, fraction: percent / 100 });
  };
}

/** Turns anything thrown into a message fit for the page; `broken` = the instance may be corrupt. */
function describe(error, doing) {
  if (error instanceof WebAssembly.RuntimeError) {
    return {
      broken: true,
      message: `The engine failed while ${doing} (internal error: ${error.message.split('\n')[0]}). ` +
        'The model on screen is unchanged. Please report the file and settings that caused it.',
    };
  }
  if (error instanceof RangeError && /memory|allocat|array buffer/i.test(error.message)) {
    return {
      broken: true,
      message: `The browser ran out of memory while ${doing}. Close other tabs or use a smaller mesh.`,
    };
  }
  const text = error instanceof Error ? error.message : String(error);
  return { broken: false, message: text || `The engine could not finish ${doing}.` };
}

const ctx = {
  mesh: null, // Mesh of the model on screen
  segmentation: null, // its current Segmentation (set by worker/segment.js)
  weldedCache: null, // { positions, indices } of `mesh`, fetched once per mesh
  describe,
  welded() {
    this.weldedCache ??= { positions: this.mesh.positions(), indices: this.mesh.indices() };
    return this.weldedCache;
  },
  memoryBytes: () => wasmMemoryBytes(),
  /**
   * Draw buffers for the current mesh, all made here so that the page only hands them to
   * WebGL: triangles grouped by patch so that each patch is one contiguous range.
   *   positions  Float32Array, 9 per triangle (expanded through the indices)
   *   colors     Uint8Array, 9 per triangle: the patch colour at each corner (palette.js)
   *   ranges     Uint32Array [start0, count0, start1, count1, …] in triangles, one pair per
   *              patch id and a last pair for the dropped triangles
   *   boxes      Float32Array [minX, minY, minZ, maxX, maxY, maxZ] per range (empty: +∞, −∞)
   *   sphere     [cx, cy, cz, radius]: centre of the bounding box and the largest distance
   *              of a vertex from it (as three.js's computeBoundingSphere finds it)
   *   borders, borderPatches   patch borders as segments and the patches beside each
   * Without a segmentation everything is "dropped". Every array is transferred.
   */
  display(progress) {
    const seg = this.segmentation;
    const { positions, indices } = this.welded();
    const triangleCount = indices.length / 3;
    const patchCount = seg ? seg.patchCount : 0;
    const patchOf = seg ? seg.patchOf() : null;
    const bucketOf = (t) => {
      const p = patchOf ? patchOf[t] : -1;
      return p < 0 ? patchCount : p;
    };
    // Counting sort: bucket sizes, then running offsets.
    const ranges = new Uint32Array(2 * (patchCount + 1));
    for (let t = 0; t < triangleCount; t++) ranges[2 * bucketOf(t) + 1]++;
    const cursor = new Uint32Array(patchCount + 1);
    for (let b = 0, start = 0; b <= patchCount; b++) {
      ranges[2 * b] = start;
      cursor[b] = start;
      start += ranges[2 * b + 1];
    }
    const out = new Float32Array(triangleCount * 9);
    const boxes = new Float32Array(6 * (patchCount + 1));
    for (let b = 0; b <= patchCount; b++) boxes.set([Infinity, Infinity, Infinity, -Infinity, -Infinity, -Infinity], 6 * b);
    const step = Math.max(1, Math.floor(triangleCount / 50));
    for (let t = 0; t < triangleCount; t++) {
      const b = bucketOf(t);
      let o = 9 * cursor[b]++;
      const box = 6 * b;
      for (let k = 0; k < 3; k++) {
        const v = 3 * indices[3 * t + k];
        for (let i = 0; i < 3; i++) {
          const x = positions[v + i];
          out[o++] = x;
          if (x < boxes[box + i]) boxes[box + i] = x;
          if (x > boxes[box + 3 + i]) boxes[box + 3 + i] = x;
        }
      }
      if (t % step === 0) progress('Preparing the display', t / triangleCount);
    }
    progress('Preparing the display', 1);
    const colors = new Uint8Array(triangleCount * 9);
    for (let b = 0; b <= patchCount; b++) {
      const start = 9 * ranges[2 * b];
      const end = start + 9 * ranges[2 * b + 1];
      if (end === start) continue;
      // One corner's colour, then doubling copies: memcpy speed on millions of corners.
      colors.set(patchColorBytes(b === patchCount ? -1 : b), start);
      for (let filled = 3; start + filled < end; filled *= 2) {
        colors.copyWithin(start + filled, start, Math.min(start + filled, end - filled));
      }
    }
    const sphere = boundingSphere(positions, boxes);
    const borders = seg ? seg.borderSegments() : new Float32Array(0);
    // The two patch ids beside each border segment, so borders of hidden patches hide too.
    const borderPatches = seg ? seg.borderPatches() : new Int32Array(0);
    const display = { positions: out, colors, ranges, boxes, sphere, borders, borderPatches };
    return [display, [out.buffer, colors.buffer, ranges.buffer, boxes.buffer, borders.buffer, borderPatches.buffer]];
  },
};

/**
 * [cx, cy, cz, r]: the bounding box's centre and the largest distance of a vertex from it.
 * The box is the union of the per-range `boxes` the display pass measured (every welded
 * vertex is a corner of some triangle), so the vertices are read once more, not twice.
 */
function boundingSphere(positions, boxes) {
  const min = [Infinity, Infinity, Infinity];
  const max = [-Infinity, -Infinity, -Infinity];
  for (let b = 0; b < boxes.length; b += 6) {
    for (let i = 0; i < 3; i++) {
      if (boxes[b + i] < min[i]) min[i] = boxes[b + i];
      if (boxes[b + 3 + i] > max[i]) max[i] = boxes[b + 3 + i];
    }
  }
  if (positions.length === 0) return [0, 0, 0, 0];
  const c = [0, 1, 2].map((i) => (min[i] + max[i]) / 2);
  let r2 = 0;
  for (let v = 0; v < positions.length; v += 3) {
    const dx = positions[v] - c[0];
    const dy = positions[v + 1] - c[1];
    const dz = positions[v + 2] - c[2];
    r2 = Math.max(r2, dx * dx + dy * dy + dz * dz);
  }
  return [...c, Math.sqrt(r2)];
}

/**
 * Picking: the first triangle along the ray (model coordinates) on a patch not in `hidden`
 * (-1 = the dropped triangles): { patchId, face, point: [x, y, z], distance } or null.
 * The core builds its ray-cast index on the first pick and keeps it with the mesh.
 */
function pick({ origin, direction, hidden = [] }) {
  const seg = ctx.segmentation;
  let hit;
  if (seg) hit = seg.raycast(origin, direction, hidden);
  else hit = hidden.includes(-1) ? null : ctx.mesh.raycast(origin, direction);
  const result = hit && { patchId: seg ? hit.patch : -1, face: hit.face, point: hit.point, distance: hit.distance };
  return [result, []];
}

/** Parses an STL, then lets each tool that sent params work on it (segment: segmenting). */
function open({ id, buffer, tools = {} }) {
  const progress = progressFor(id);
  const t0 = performance.now();
  // Parse first: a bad file leaves the current mesh (and everything derived) untouched.
  const next = Mesh.fromStl(new Uint8Array(buffer), progress);
  for (const tool of Object.values(TOOLS)) tool.onMeshChanged?.(ctx);
  ctx.mesh?.free();
  ctx.mesh = next;
  ctx.weldedCache = null;
  const report = ctx.mesh.report();
  const t1 = performance.now();
  const toolResults = {};
  for (const [name, params] of Object.entries(tools)) {
    if (params && TOOLS[name]?.onOpen) toolResults[name] = TOOLS[name].onOpen(ctx, params, progress);
  }
  const [display, transfer] = ctx.display(progress);
  const result = {
    report,
    triangleCount: ctx.mesh.triangleCount,
    vertexCount: ctx.mesh.vertexCount,
    tools: toolResults,
    display,
    memoryBytes: wasmMemoryBytes(),
    timings: { parseMs: t1 - t0 },
  };
  return [result, transfer];
}

function handlerOf(op) {
  if (op === 'open') return (msg) => open(msg);
  if (op === 'display') {
    return (msg) => {
      if (!ctx.mesh) throw new Error('No model is loaded.');
      return ctx.display(progressFor(msg.id));
    };
  }
  if (op === 'pick') {
    return (msg) => {
      if (!ctx.mesh) throw new Error('No model is loaded.');
      return pick(msg);
    };
  }
  const [tool, name] = op.split('.');
  const handler = TOOLS[tool]?.ops?.[name];
  if (!handler) return null;
  return (msg) => {
    if (!ctx.mesh && !TOOLS[tool].meshFree?.includes(name)) throw new Error('No model is loaded.');
    return handler(ctx, msg, progressFor(msg.id));
  };
}

const DOING = { open: 'reading the file', pick: 'picking', display: 'preparing the display' };

/** Idle time after a request before the warm-up runs (a request meanwhile puts it off). */
const WARM_UP_IDLE_MS = 1000;
let warmUpTimer = null;
let warmedUp = false;

/**
 * Once a model is open, warms the geodesic code up (see warm-up.js) when no request has come
 * for WARM_UP_IDLE_MS, so that it never delays one the page is waiting for; once per worker.
 */
function warmUpWhenIdle() {
  clearTimeout(warmUpTimer);
  if (warmedUp || !ctx.mesh) return;
  warmUpTimer = setTimeout(() => {
    warmedUp = true;
    try {
      warmUp(Mesh);
    } catch (error) {
      // A failure here is a bug, not the user's: say so in the console, and the next request
      // reports it as usual if the engine is broken.
      console.warn(`skinpath: the engine's warm-up failed: ${error?.message ?? error}`);
    }
  }, WARM_UP_IDLE_MS);
}

try {
  await init();
  self.addEventListener('message', (event) => {
    const msg = event.data;
    clearTimeout(warmUpTimer);
    try {
      const handler = handlerOf(msg.op);
      if (!handler) throw new Error(`Unknown engine request "${msg.op}".`);
      const [result, transfer] = handler(msg);
      postMessage({ id: msg.id, type: 'done', result }, transfer);
    } catch (error) {
      const [tool, name] = msg.op.split('.');
      const doing = DOING[msg.op] ?? TOOLS[tool]?.doing?.[name] ?? 'working';
      const d = describe(error, doing);
      postMessage({ id: msg.id, type: 'error', message: d.message, broken: d.broken });
    }
    warmUpWhenIdle();
  });
  postMessage({ type: 'ready' });
} catch (error) {
  postMessage({ type: 'fatal', message: `The WebAssembly engine could not start: ${error?.message ?? error}` });
}
