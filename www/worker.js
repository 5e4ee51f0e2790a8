// Module worker: owns the wasm Mesh and Segmentation so that re-segmenting never re-parses,
// and turns their results into ready-to-draw buffers (transferred, not copied).
// Protocol: see engine.js. Workers ignore the page's import map, hence the relative path.
import init, { Mesh, wasmMemoryBytes } from './pkg/skinpath.js';
import { zipSync } from './vendor/fflate/esm/browser.js';

let mesh = null; // Mesh of the model on screen
let segmentation = null; // its current Segmentation
let welded = null; // { positions, indices } of `mesh`, fetched once per mesh

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

function getWelded() {
  welded ??= { positions: mesh.positions(), indices: mesh.indices() };
  return welded;
}

/**
 * Draw buffers for the current mesh, triangles grouped by patch so that each patch is one
 * contiguous range: positions (9 floats per triangle, expanded through the indices) and
 * ranges [start0, count0, start1, count1, …] in triangles, one pair per patch id and a
 * last pair for the dropped triangles. Without a segmentation everything is "dropped".
 */
function buildDisplay(seg, progress) {
  const { positions, indices } = getWelded();
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
  const step = Math.max(1, Math.floor(triangleCount / 50));
  for (let t = 0; t < triangleCount; t++) {
    let o = 9 * cursor[bucketOf(t)]++;
    for (let k = 0; k < 3; k++) {
      const v = 3 * indices[3 * t + k];
      out[o++] = positions[v];
      out[o++] = positions[v + 1];
      out[o++] = positions[v + 2];
    }
    if (t % step === 0) progress('Preparing the display', t / triangleCount);
  }
  progress('Preparing the display', 1);
  const borders = seg ? seg.borderSegments() : new Float32Array(0);
  // The two patch ids beside each border segment, so borders of hidden patches hide too.
  const borderPatches = seg ? seg.borderPatches() : new Int32Array(0);
  return { positions: out, ranges, borders, borderPatches };
}

function summarize(seg) {
  return {
    patchCount: seg.patchCount,
    threshold: seg.threshold,
    thresholdKind: seg.thresholdKind,
    patches: seg.patches(),
  };
}

function transferList(display) {
  return [display.positions.buffer, display.ranges.buffer, display.borders.buffer, display.borderPatches.buffer];
}

/** Segments `mesh`; the previous segmentation survives a failure. */
function segment(params, progress) {
  const next = mesh.segment(params, progress);
  segmentation?.free();
  segmentation = next;
  return segmentation;
}

const handlers = {
  open({ id, buffer, params }) {
    const progress = progressFor(id);
    const t0 = performance.now();
    // Parse first: a bad file leaves the current mesh (and its segmentation) untouched.
    const next = Mesh.fromStl(new Uint8Array(buffer), progress);
    segmentation?.free();
    segmentation = null;
    mesh?.free();
    mesh = next;
    welded = null;
    const report = mesh.report();
    const t1 = performance.now();

    let summary = null;
    let segmentError = null;
    if (params) {
      try {
        summary = summarize(segment(params, progress));
      } catch (error) {
        const d = describe(error, 'segmenting');
        if (d.broken) throw error;
        segmentError = d.message; // the model still shows, uncoloured; the form says why
      }
    }
    const t2 = performance.now();
    const display = buildDisplay(segmentation, progress);
    const result = {
      report,
      triangleCount: mesh.triangleCount,
      vertexCount: mesh.vertexCount,
      segmentation: summary,
      segmentError,
      display,
      memoryBytes: wasmMemoryBytes(),
      timings: { parseMs: t1 - t0, segmentMs: summary ? t2 - t1 : null },
    };
    return [result, transferList(display)];
  },

  segment({ id, params }) {
    if (!mesh) throw new Error('No model is loaded.');
    const progress = progressFor(id);
    const t0 = performance.now();
    const summary = summarize(segment(params, progress));
    const t1 = performance.now();
    const display = buildDisplay(segmentation, progress);
    const result = { segmentation: summary, display, memoryBytes: wasmMemoryBytes(), timings: { segmentMs: t1 - t0 } };
    return [result, transferList(display)];
  },

  patchStl({ patchId }) {
    if (!segmentation) throw new Error('There is no segmentation to export.');
    const bytes = ownBuffer(segmentation.patchStl(patchId));
    return [bytes, [bytes.buffer]];
  },

  zip({ id, names }) {
    if (!segmentation) throw new Error('There is no segmentation to export.');
    const progress = progressFor(id);
    const files = {};
    names.forEach(({ patchId, fileName }, i) => {
      progress('Writing patch files', i / names.length);
      files[fileName] = segmentation.patchStl(patchId);
    });
    progress('Compressing', 0);
    // Level 1: binary float data barely compresses further at higher levels, and speed matters.
    const zipped = zipSync(files, { level: 1 });
    progress('Compressing', 1);
    return [zipped, [zipped.buffer]];
  },
};

/** Detaches a typed array from a larger buffer so that only its bytes are transferred. */
function ownBuffer(view) {
  return view.byteOffset === 0 && view.byteLength === view.buffer.byteLength ? view : view.slice();
}

const doing = { open: 'reading the file', segment: 'segmenting', patchStl: 'writing the patch', zip: 'writing the archive' };

try {
  await init();
  self.addEventListener('message', (event) => {
    const msg = event.data;
    try {
      const [result, transfer] = handlers[msg.op](msg);
      postMessage({ id: msg.id, type: 'done', result }, transfer);
    } catch (error) {
      const d = describe(error, doing[msg.op] ?? 'working');
      postMessage({ id: msg.id, type: 'error', message: d.message, broken: d.broken });
    }
  });
  postMessage({ type: 'ready' });
} catch (error) {
  postMessage({ type: 'fatal', message: `The WebAssembly engine could not start: ${error?.message ?? error}` });
}
