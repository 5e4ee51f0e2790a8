// Worker side of the spray tool (tools/spray.js): plans on the mesh held by the worker, keeps
// the last SprayPlan for the exports, and writes export files (zipped when there are several).
// Protocol and `ctx`: see worker.js. Parameters arrive already in the file's units.
import { exportTexts, packageFiles } from './programs.js';

export const doing = { plan: 'planning the spray trajectory', exportPlan: 'writing the spray program' };

let plan = null; // SprayPlan of the result on screen

export function onMeshChanged() {
  plan?.free();
  plan = null;
}

/**
 * The core splits each face into k² sub-triangles, k = ceil(longest edge / resolution) but at
 * most ceil(2·√area / resolution) (so slivers stay cheap), so long slender faces cost more
 * samples than their area suggests. Returns the finest resolution (≥ `resolution`) whose
 * sample count stays within `budget`, counting (k+1)(k+2)/2 points a face (an upper bound:
 * shared edge points count twice). No paper: a bisection on a count that falls as the
 * resolution grows; 40 steps at most.
 */
function fitResolution(ctx, faces, resolution, budget) {
  const { positions: P, indices: I } = ctx.welded();
  const n = faces ? faces.length : I.length / 3;
  const longest = new Float64Array(n);
  const root = new Float64Array(n); // 2·√area
  for (let i = 0; i < n; i++) {
    const f = faces ? faces[i] : i;
    const [a, b, c] = [3 * I[3 * f], 3 * I[3 * f + 1], 3 * I[3 * f + 2]];
    const d = (u, v) => Math.hypot(P[u] - P[v], P[u + 1] - P[v + 1], P[u + 2] - P[v + 2]);
    longest[i] = Math.max(d(a, b), d(b, c), d(c, a));
    const [ux, uy, uz] = [P[b] - P[a], P[b + 1] - P[a + 1], P[b + 2] - P[a + 2]];
    const [vx, vy, vz] = [P[c] - P[a], P[c + 1] - P[a + 1], P[c + 2] - P[a + 2]];
    const area = 0.5 * Math.hypot(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx);
    root[i] = 2 * Math.sqrt(area);
  }
  const count = (r) => {
    let total = 0;
    for (let i = 0; i < n; i++) {
      const k = Math.max(1, Math.min(Math.ceil(longest[i] / r), Math.ceil(root[i] / r)));
      total += ((k + 1) * (k + 2)) / 2;
    }
    return total;
  };
  if (count(resolution) <= budget) return resolution;
  let lo = resolution;
  let hi = resolution * 2;
  for (let i = 0; i < 40 && count(hi) > budget; i++) {
    lo = hi;
    hi *= 2;
  }
  for (let i = 0; i < 40 && hi - lo > 1e-3 * hi; i++) {
    const mid = (lo + hi) / 2;
    if (count(mid) > budget) lo = mid;
    else hi = mid;
  }
  return hi;
}

export const ops = {
  /**
   * { params, patchId | null, sampleBudget? } → arrays to draw and the figures; the plan
   * stays here. With a sampleBudget the evaluation resolution is coarsened to fit it.
   */
  plan(ctx, { params, patchId, sampleBudget }, progress) {
    let faces;
    if (patchId !== null && patchId !== undefined) {
      if (!ctx.segmentation) throw new Error('There is no segmentation: segment the model or plan on the whole mesh.');
      faces = ctx.segmentation.patchFaces(patchId);
    }
    const radius = params.standoff * Math.tan(params.coneAngle / 2);
    const wanted = params.resolution ?? radius / 8;
    const resolution = sampleBudget ? fitResolution(ctx, faces, wanted, sampleBudget) : wanted;
    if (resolution !== wanted) params = { ...params, resolution };
    const t0 = performance.now();
    const next = ctx.mesh.planSpray(params, faces, progress);
    const ms = performance.now() - t0;
    plan?.free();
    plan = next;
    const result = {
      spacing: plan.spacing,
      speed: plan.speed,
      passCount: plan.passCount,
      // Gun speeds (file unit/s): the move arriving at each trajectory point, the commanded
      // gun-on range, and the times and lengths they give.
      speeds: plan.speeds(),
      speedOptimised: plan.speedOptimised,
      minSpeed: plan.minSpeed,
      maxSpeed: plan.maxSpeed,
      cycleTime: plan.cycleTime,
      sprayLength: plan.sprayLength,
      pathLength: plan.pathLength,
      rasterAngle: plan.rasterAngle,
      directions: plan.directions(),
      hotspots: plan.hotspots(),
      trajectory: plan.trajectory(),
      kinds: plan.pointKinds(),
      passOf: plan.passOf(),
      samplePositions: plan.samplePositions(),
      sampleThickness: plan.sampleThickness(),
      sampleTriangles: plan.sampleTriangles(),
      quality: plan.quality(),
      iterations: plan.iterations(),
      resolution,
      coarsened: resolution > wanted,
      memoryBytes: ctx.memoryBytes(),
      timings: { planMs: ms },
    };
    const transfer = ['speeds', 'trajectory', 'kinds', 'passOf', 'samplePositions', 'sampleThickness', 'sampleTriangles']
      .map((k) => result[k].buffer);
    return [result, transfer];
  },

  /**
   * { format: 'csv'|'json'|'rapid'|'krl', options, stem } → { fileName, bytes, fileCount }:
   * one file as it is, several in one ZIP archive.
   */
  exportPlan(ctx, { format, options, stem }, progress) {
    if (!plan) throw new Error('NO_PLAN');
    progress('Writing the program', 0);
    return packageFiles(exportTexts(plan, format, options), format, `${stem}_spray`, progress);
  },

  drop() {
    onMeshChanged();
    return [null, []];
  },
};
