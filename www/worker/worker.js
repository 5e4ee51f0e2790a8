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
// Requests run one at a time, in order (one that waits for a file's bytes holds the ones
// after it). Typed arrays in results are transferred, not copied. 'open' takes { file } (a
// File, read as a stream into the engine, never held whole) or { buffer } (an ArrayBuffer).
// Once a model is open and no request has come for a second, the worker warms the geodesic
// and spray code up (warm-up.js), once: the Paths tool's first distance and the Spray tool's
// first plan then run optimised code.
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
import init, { Mesh, StlReader, wasmMemoryBytes } from '../pkg/skinpath.js';
import * as segmentTool from './segment.js';
import * as sprayTool from './spray.js';
import * as drillTool from './drill.js';
import * as pathsTool from './paths.js';
import { patchColorBytes } from '../viewer/palette.js';
import { WARM_UP_STEPS } from './warm-up.js';

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
   * WebGL: triangles grouped by patch so that each patch is one contiguous range, in indexed
   * chunks with vertices of their own (see the core's `DisplayBuffers`).
   *   positions  Float32Array, xyz per vertex (a vertex on a patch border is copied for each
   *              patch, so that its colour is the patch's)
   *   indices    Uint16Array, 3 per triangle, into its chunk's vertices
   *   chunks     Uint32Array [firstTriangle, triangles, firstVertex, vertices] per chunk
   *   colors     Uint8Array, 3 per vertex: its patch colour (palette.js)
   *   ranges     Uint32Array [start0, count0, start1, count1, …] in triangles, one pair per
   *              patch id and a last pair for the dropped triangles
   *   boxes      Float32Array [minX, minY, minZ, maxX, maxY, maxZ] per range (empty: +∞, −∞)
   *   sphere     [cx, cy, cz, radius]: centre of the bounding box and the largest distance
   *              of a vertex from it (as three.js's computeBoundingSphere finds it)
   *   borders, borderPatches   patch borders as segments and the patches beside each
   * Without a segmentation everything is "dropped". The engine groups and writes the
   * triangles (`displayBuffers`); the colours are filled here. Every array is transferred.
   */
  display(progress) {
    const seg = this.segmentation;
    const { positions, indices, chunks, runs, ranges, boxes, sphere } = (seg ?? this.mesh).displayBuffers(progress);
    const vertexCount = positions.length / 3;
    const patchCount = ranges.length / 2 - 1;
    const colors = new Uint8Array(3 * vertexCount);
    for (let r = 0; r < runs.length; r += 2) {
      const start = 3 * runs[r];
      const end = 3 * (r + 2 < runs.length ? runs[r + 2] : vertexCount);
      if (end === start) continue;
      // One vertex's colour, then doubling copies: memcpy speed on millions of vertices.
      colors.set(patchColorBytes(runs[r + 1] === patchCount ? -1 : runs[r + 1]), start);
      for (let filled = 3; start + filled < end; filled *= 2) {
        colors.copyWithin(start + filled, start, Math.min(start + filled, end - filled));
      }
    }
    const borders = seg ? seg.borderSegments() : new Float32Array(0);
    // The two patch ids beside each border segment, so borders of hidden patches hide too.
    const borderPatches = seg ? seg.borderPatches() : new Int32Array(0);
    const display = { positions, indices, chunks, colors, ranges, boxes, sphere, borders, borderPatches };
    return [display, [positions.buffer, indices.buffer, chunks.buffer, colors.buffer, ranges.buffer, boxes.buffer,
      borders.buffer, borderPatches.buffer]];
  },
};

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

/**
 * A File's bytes streamed into the engine as they are read (a 200 MB file is never held
 * whole, in the page or here): the Mesh. Errors name the file's problem.
 */
async function readFile(file, progress) {
  const reader = new StlReader(file.size, progress);
  try {
    const stream = file.stream().getReader();
    for (;;) {
      let piece;
      try {
        piece = await stream.read();
      } catch {
        throw new Error('the file can no longer be read (was it moved or deleted?); open it again');
      }
      if (piece.done) break;
      reader.push(piece.value);
    }
    return reader.finish();
  } finally {
    reader.free();
  }
}

/** Parses an STL, then lets each tool that sent params work on it (segment: segmenting). */
async function open({ id, file, buffer, tools = {} }) {
  const progress = progressFor(id);
  const t0 = performance.now();
  // Parse first: a bad file leaves the current mesh (and everything derived) untouched.
  const next = file ? await readFile(file, progress) : Mesh.fromStl(new Uint8Array(buffer), progress);
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

/** Idle time before each step of the warm-up runs (a request meanwhile puts it off). */
const WARM_UP_IDLE_MS = 1000;
let warmUpTimer = null;
/** Steps of the warm-up done (each runs once per worker). */
let warmUpDone = 0;

/**
 * Once a model is open, warms the geodesic and spray code up (see warm-up.js), one step each
 * time no request has come for WARM_UP_IDLE_MS, so that a request the page is waiting for
 * waits for one step at most; once per worker.
 */
function warmUpWhenIdle() {
  clearTimeout(warmUpTimer);
  if (warmUpDone >= WARM_UP_STEPS.length || !ctx.mesh) return;
  warmUpTimer = setTimeout(() => {
    const step = WARM_UP_STEPS[warmUpDone];
    warmUpDone += 1;
    try {
      step(Mesh);
    } catch (error) {
      // A failure here is a bug, not the user's: say so in the console, and the next request
      // reports it as usual if the engine is broken.
      console.warn(`skinpath: the engine's warm-up failed: ${error?.message ?? error}`);
    }
    warmUpWhenIdle();
  }, WARM_UP_IDLE_MS);
}

try {
  await init();
  // Requests run one at a time in order: one that awaits (a file's stream) holds the rest.
  let queue = Promise.resolve();
  const handle = async (msg) => {
    clearTimeout(warmUpTimer);
    try {
      const handler = handlerOf(msg.op);
      if (!handler) throw new Error(`Unknown engine request "${msg.op}".`);
      const [result, transfer] = await handler(msg);
      postMessage({ id: msg.id, type: 'done', result }, transfer);
    } catch (error) {
      const [tool, name] = msg.op.split('.');
      const doing = DOING[msg.op] ?? TOOLS[tool]?.doing?.[name] ?? 'working';
      const d = describe(error, doing);
      postMessage({ id: msg.id, type: 'error', message: d.message, broken: d.broken });
    }
    warmUpWhenIdle();
  };
  self.addEventListener('message', (event) => {
    clearTimeout(warmUpTimer);
    queue = queue.then(() => handle(event.data));
  });
  postMessage({ type: 'ready' });
} catch (error) {
  postMessage({ type: 'fatal', message: `The WebAssembly engine could not start: ${error?.message ?? error}` });
}
