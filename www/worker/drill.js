// Worker side of the drilling tool (tools/drill.js): reads hole lists, gives normals from the
// mesh or from four laser readings, corrects the holes with both methods, writes the drilling
// program, and hands out the paper's built-in example. Protocol and `ctx`: see worker.js.
// Everything arrives and leaves in the file's units (robot programs are written in mm).
import { packageFiles } from './programs.js';
import { drillPaperExample, normalFromLasers, parseHolesCsv } from '../pkg/skinpath.js';

export const doing = {
  example: 'building the example panel',
  parseHoles: 'reading the hole list',
  meshNormals: 'finding the mesh normals',
  laserReadings: 'simulating the laser readings',
  laserNormals: 'computing normals from the laser readings',
  correct: 'correcting the holes',
  program: 'writing the drilling program',
};

/** Ops that do not need a model on screen. */
export const meshFree = ['example', 'parseHoles', 'laserNormals'];

export const ops = {
  /** → DrillPaperExample (STL bytes, references, ids, nominal holes, truth). */
  example() {
    const ex = drillPaperExample();
    return [ex, [ex.stl.buffer, ex.holes.buffer, ex.truth.buffer]];
  },

  /** { text } → HoleList. */
  parseHoles(ctx, { text }) {
    const list = parseHolesCsv(text);
    return [list, [list.positions.buffer, list.lines.buffer]];
  },

  /** { points } (flat xyz) → ClosestPoints of the mesh. */
  meshNormals(ctx, { points }) {
    const found = ctx.mesh.closestPoints(Float64Array.from(points));
    return [found, []];
  },

  /** { origins, directions } (flat xyz, 4 per reference) → distances (NaN where a beam misses). */
  laserReadings(ctx, { origins, directions }) {
    const r = ctx.mesh.laserReadings(Float64Array.from(origins), Float64Array.from(directions));
    return [Float64Array.from(r), []];
  },

  /** { heads: [{ origins, directions, readings }] } → one unit normal or { error } per head. */
  laserNormals(ctx, { heads }) {
    const out = heads.map((h) => {
      try {
        return { normal: normalFromLasers(Float64Array.from(h.origins), Float64Array.from(h.directions), Float64Array.from(h.readings)) };
      } catch (error) {
        return { error: error.message };
      }
    });
    return [out, []];
  },

  /** { params } (CorrectionParams without method) → { coons, bilinear } HoleCorrections. */
  correct(ctx, { params }, progress) {
    progress('Correcting with the Coons patch', 0);
    const coons = ctx.mesh.correctHoles({ ...params, method: 'coons' });
    progress('Correcting with bilinear interpolation', 0.5);
    const bilinear = ctx.mesh.correctHoles({ ...params, method: 'bilinear' });
    const transfer = [coons, bilinear].flatMap((c) => [c.corrected.buffer, c.normals.buffer, c.u.buffer, c.w.buffer, c.outside.buffer]);
    return [{ coons, bilinear }, transfer];
  },

  /**
   * { params, pose, format: 'csv'|'json'|'rapid'|'krl', options, stem } → { fileName, bytes,
   * fileCount }: one file as it is, several in one ZIP archive.
   */
  program(ctx, { params, pose, format, options, stem }, progress) {
    progress('Writing the program', 0);
    const texts = ctx.mesh.drillingProgram(params, pose, format, options);
    return packageFiles(texts, format, `${stem}_drill`, progress);
  },
};
