// Worker side of the segmentation tool (tools/segment.js): segmenting the mesh held by the
// worker, and the patch STL exports. Protocol and `ctx`: see worker.js.
import { zipSync } from '../vendor/fflate/esm/browser.js';

export const doing = { run: 'segmenting', patchStl: 'writing the patch', zip: 'writing the archive' };

function summarize(seg) {
  return { patchCount: seg.patchCount, threshold: seg.threshold, thresholdKind: seg.thresholdKind, patches: seg.patches() };
}

/** Segments ctx.mesh; the previous segmentation survives a failure. */
function segment(ctx, params, progress) {
  const next = ctx.mesh.segment(params, progress);
  ctx.segmentation?.free();
  ctx.segmentation = next;
  return ctx.segmentation;
}

/** Detaches a typed array from a larger buffer so that only its bytes are transferred. */
function ownBuffer(view) {
  return view.byteOffset === 0 && view.byteLength === view.buffer.byteLength ? view : view.slice();
}

export function onMeshChanged(ctx) {
  ctx.segmentation?.free();
  ctx.segmentation = null;
}

/** Right after parsing: { segmentation, segmentError, segmentMs }; the model shows either way. */
export function onOpen(ctx, params, progress) {
  const t0 = performance.now();
  try {
    return { segmentation: summarize(segment(ctx, params, progress)), segmentError: null, segmentMs: performance.now() - t0 };
  } catch (error) {
    const d = ctx.describe(error, 'segmenting');
    if (d.broken) throw error;
    return { segmentation: null, segmentError: d.message, segmentMs: null };
  }
}

export const ops = {
  run(ctx, { params }, progress) {
    const t0 = performance.now();
    const summary = summarize(segment(ctx, params, progress));
    const t1 = performance.now();
    const [display, transfer] = ctx.display(progress);
    return [{ segmentation: summary, display, memoryBytes: ctx.memoryBytes(), timings: { segmentMs: t1 - t0 } }, transfer];
  },

  patchStl(ctx, { patchId }) {
    if (!ctx.segmentation) throw new Error('There is no segmentation to export.');
    const bytes = ownBuffer(ctx.segmentation.patchStl(patchId));
    return [bytes, [bytes.buffer]];
  },

  zip(ctx, { names }, progress) {
    if (!ctx.segmentation) throw new Error('There is no segmentation to export.');
    const files = {};
    names.forEach(({ patchId, fileName }, i) => {
      progress('Writing patch files', i / names.length);
      files[fileName] = ctx.segmentation.patchStl(patchId);
    });
    progress('Compressing', 0);
    // Level 1: binary float data barely compresses further at higher levels, and speed matters.
    const zipped = zipSync(files, { level: 1 });
    progress('Compressing', 1);
    return [zipped, [zipped.buffer]];
  },
};
