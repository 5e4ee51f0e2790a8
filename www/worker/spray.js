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

export const ops = {
  /**
   * { params, patchId | null, sampleBudget? } → arrays to draw and the figures; the plan
   * stays here. With a sampleBudget the core coarsens the evaluation resolution to fit it.
   */
  plan(ctx, { params, patchId, sampleBudget }, progress) {
    let faces;
    if (patchId !== null && patchId !== undefined) {
      if (!ctx.segmentation) throw new Error('There is no segmentation: segment the model or plan on the whole mesh.');
      faces = ctx.segmentation.patchFaces(patchId);
    }
    if (sampleBudget) params = { ...params, sampleBudget };
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
      resolution: plan.resolution,
      // The resolution asked for: the one given, or the core's default R/8.
      coarsened: plan.resolution > (params.resolution ?? (params.standoff * Math.tan(params.coneAngle / 2)) / 8),
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
