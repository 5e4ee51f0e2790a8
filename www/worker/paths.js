// Worker side of the paths tool (tools/paths.js): the geodesic distance from a source (a
// section plane, a boundary loop) by the accurate, the exact, the fast or the voxel method, its iso-distance passes,
// and the tool-path exports. Keeps the last DistanceField for the exports. Protocol and
// `ctx`: see worker.js. Lengths arrive and leave in the file's units.
import { reserveMemory } from '../pkg/skinpath.js';
import { exportTexts, packageFiles } from './programs.js';
import { reserveFirstDistance } from './warm-up.js';

const METHOD_NAMES = { accurate: 'Accurate', exact: 'Exact', fast: 'Fast', mesh: 'Fast', voxel: 'Voxel' };

export const doing = {
  prepare: 'preparing for the first distance',
  compute: 'computing the geodesic distance',
  exportPaths: 'writing the path program',
};

let field = null; // DistanceField of the result on screen
let pathSpec = null; // { spacing, pathOptions } it was cut with
let prepared = false; // whether the model's first distance is prepared (its surface, its memory)

export function onMeshChanged() {
  field?.free();
  field = null;
  pathSpec = null;
  prepared = false;
}

/** Flattens iso-paths into one transferable array and a table of { level, distance, closed, start, count }. */
function packPaths(paths) {
  let total = 0;
  for (const p of paths) total += p.points.length;
  const points = new Float32Array(total);
  const table = [];
  let at = 0;
  for (const p of paths) {
    points.set(p.points, at);
    let length = 0;
    const q = p.points;
    for (let i = 3; i < q.length; i += 3) length += Math.hypot(q[i] - q[i - 3], q[i + 1] - q[i - 2], q[i + 2] - q[i - 1]);
    if (p.closed && q.length >= 6) {
      const n = q.length;
      length += Math.hypot(q[0] - q[n - 3], q[1] - q[n - 2], q[2] - q[n - 1]);
    }
    table.push({ level: p.level, distance: p.distance, closed: p.closed, start: at / 3, count: q.length / 3, length });
    at += q.length;
  }
  return { points, table };
}

/** Centre of the mesh's bounding box (the plane's point when none was clicked). */
function boxCentre(ctx) {
  const P = ctx.welded().positions;
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < P.length; i += 3) {
    for (let k = 0; k < 3; k++) {
      lo[k] = Math.min(lo[k], P[i + k]);
      hi[k] = Math.max(hi[k], P[i + k]);
    }
  }
  return [0, 1, 2].map((k) => (lo[k] + hi[k]) / 2);
}

export const ops = {
  /**
   * {} → { reserved, memoryBytes }: derives what a distance on the whole model needs from the
   * mesh (mesh.prepareGeodesic) and grows the engine's memory by what the model's first
   * accurate distance will take (see warm-up.js), once per model; the tool asks when it is
   * opened.
   */
  prepare(ctx) {
    // What the first distance on the whole model derives from the mesh (the faces around
    // each vertex, the face normals), then the memory the distance itself will take.
    if (!prepared) ctx.mesh.prepareGeodesic();
    const reserved = prepared || reserveFirstDistance(reserveMemory, ctx.mesh.triangleCount);
    prepared = true;
    return [{ reserved, memoryBytes: ctx.memoryBytes() }, []];
  },

  /**
   * { source: { kind: 'plane', point|null, normal } | { kind: 'boundary', loop? }
   *   | { kind: 'points', points (flat xyz), closed }, patchId|null,
   *   methods: ['accurate'|'exact'|'fast'|'voxel', …], voxelSize, spacing, pathOptions } → per method the vertex
   * distances, and for the first method its paths and a trace of the source. The first
   * method's field stays here for the exports.
   */
  compute(ctx, { source, patchId, methods, voxelSize, spacing, pathOptions }, progress) {
    let faces;
    if (patchId !== null && patchId !== undefined) {
      if (!ctx.segmentation) throw new Error('There is no segmentation: segment the model or use the whole mesh.');
      faces = ctx.segmentation.patchFaces(patchId);
    }
    let src;
    if (source.kind === 'plane') src = { plane: { point: source.point ?? boxCentre(ctx), normal: source.normal } };
    else if (source.kind === 'points') src = { polyline: Float64Array.from(source.points), closed: source.closed };
    else src = { boundaryOf: patchId === null || patchId === undefined ? 'mesh' : patchId, ...(source.loop !== undefined ? { loop: source.loop } : {}) };
    const out = { runs: [], point: src.plane?.point ?? null };
    const transfer = [];
    let kept = null;
    try {
      methods.forEach((method, i) => {
        const params = { method, ...(faces ? { faces } : {}), ...(method === 'voxel' && voxelSize ? { voxelSize } : {}) };
        const t0 = performance.now();
        const f = ctx.mesh.geodesicDistance(src, params,
          (stage, fraction) => progress(`${METHOD_NAMES[method]} method: ${stage}`, (i + fraction) / methods.length));
        const ms = performance.now() - t0;
        const run = { method, ran: f.method, maxDistance: f.maxDistance, vertexDistance: f.vertexDistance(), ms, voxelCount: f.voxelCount };
        transfer.push(run.vertexDistance.buffer);
        if (i === 0) {
          kept = f;
          progress('Cutting the passes', null);
          const { points, table } = packPaths(f.isoPaths(spacing, pathOptions));
          run.points = points;
          run.table = table;
          transfer.push(points.buffer);
          // The source, traced as the iso-line a hair away from it.
          const eps = Math.max(f.maxDistance * 1e-4, 1e-9);
          const trace = packPaths(f.isoPaths(eps, { maxLevel: 1, pointSpacing: Math.max(spacing / 4, eps) }));
          run.source = trace.points;
          run.sourceTable = trace.table;
          transfer.push(trace.points.buffer);
        } else {
          f.free();
        }
        out.runs.push(run);
      });
    } catch (error) {
      kept?.free();
      throw error;
    }
    field?.free();
    field = kept;
    pathSpec = { spacing, pathOptions };
    // The welded mesh, for the colour map.
    const { positions, indices } = ctx.welded();
    out.positions = Float32Array.from(positions);
    out.indices = Uint32Array.from(indices);
    transfer.push(out.positions.buffer, out.indices.buffer);
    out.memoryBytes = ctx.memoryBytes();
    return [out, transfer];
  },

  /**
   * { format: 'csv'|'json'|'rapid'|'krl', options, order, stem } → { fileName, bytes,
   * fileCount }: one file as it is, several in one ZIP archive.
   */
  exportPaths(ctx, { format, options, stem }, progress) {
    if (!field) throw new Error('NO_PATHS');
    progress('Writing the program', 0);
    const path = field.toolPath(pathSpec.spacing, pathSpec.pathOptions);
    let texts;
    try {
      texts = exportTexts(path, format, options);
    } finally {
      path.free();
    }
    return packageFiles(texts, format, `${stem}_paths`, progress);
  },
};
