// Warm-up of the engine's geodesic and spray code, run by the worker once a model is open and
// it is idle.
//
// Why: a WebAssembly engine (V8 in Chrome, Edge and Node) first runs each function's quickly
// compiled baseline code and swaps in optimised code only once it has run hot, and never
// within a call already running: a function called once (the whole of a distance's set-up, its
// focal refinement) runs baseline code to its end. So the Paths tool's first distance on a
// model took about 1.4 times as long as the same distance again (500k-triangle curved
// panel: 0.23 s against 0.16 s). Three distances on a small generated cap and sphere, which
// take the same code paths as a real panel's (a boundary, a plane section, a point source,
// with focal points), make that code hot while the user is still looking at the model;
// `npm run bench -- geodesic` times a first call after it as the page's. The same holds for
// the spray planner (its samples, the search's screening, the speed optimiser's matrices):
// the first plan on the 747's largest patch at the page's sample budget took 0.75–0.89 s in
// Node, the next 0.57–0.58 s; after a small search on a cap, 0.62–0.63 s.
//
// Cost: about two tenths of a second of the worker's idle time, in two steps of about a tenth
// (one per idle second), and a few megabytes of memory, freed at once. It runs once per worker (Cancel replaces the worker, whose next model warms
// it again).

/**
 * Binary STL of a latitude-longitude cap of the unit sphere scaled by `radius`: a pole vertex
 * at the top and `rings` rings of `sectors` vertices down to polar angle `theta0`; with
 * `theta0 = π` the last ring is replaced by the other pole (a closed sphere).
 */
export function capStl(rings, sectors, theta0, radius) {
  const closed = theta0 >= Math.PI;
  const ringCount = closed ? rings - 1 : rings;
  const vertices = [[0, 0, radius]];
  for (let i = 1; i <= ringCount; i++) {
    const th = (theta0 * i) / rings;
    for (let k = 0; k < sectors; k++) {
      const ph = (2 * Math.PI * (k + 0.5 * (i % 2))) / sectors;
      vertices.push([radius * Math.sin(th) * Math.cos(ph), radius * Math.sin(th) * Math.sin(ph), radius * Math.cos(th)]);
    }
  }
  if (closed) vertices.push([0, 0, -radius]);
  const at = (i, k) => 1 + (i - 1) * sectors + (k % sectors);
  const triangles = [];
  for (let k = 0; k < sectors; k++) triangles.push([0, at(1, k), at(1, k + 1)]);
  for (let i = 1; i < ringCount; i++) {
    // Odd rings are turned by half a sector: each quad splits along its shorter diagonal.
    const s = i % 2;
    for (let k = 0; k < sectors; k++) {
      triangles.push([at(i, k), at(i + 1, k + 1 - s), at(i, k + 1)]);
      triangles.push([at(i, k + s), at(i + 1, k), at(i + 1, k + 1)]);
    }
  }
  if (closed) {
    const south = vertices.length - 1;
    for (let k = 0; k < sectors; k++) triangles.push([south, at(ringCount, k + 1), at(ringCount, k)]);
  }
  const bytes = new Uint8Array(84 + 50 * triangles.length);
  const view = new DataView(bytes.buffer);
  view.setUint32(80, triangles.length, true);
  let o = 84;
  for (const t of triangles) {
    o += 12;
    for (const v of t) for (const c of vertices[v]) { view.setFloat32(o, c, true); o += 4; }
    o += 2;
  }
  return bytes;
}

/**
 * The spray warm-up: a spacing search with the page's defaults (millimetres, 40° cone, 250 mm
 * standoff, speeds optimised) on a faceted cap of radius 1 m, at a sample budget small enough
 * to take a few hundredths of a second, large enough that the search screens on coarse
 * samples before it confirms at full resolution.
 */
export const SPRAY_WARM_UP = {
  cap: [12, 48, 0.8, 1000],
  params: {
    spacing: 90, standoff: 250, speed: 400, flowRate: 2500, coneAngle: (40 * Math.PI) / 180,
    transitionAngle: (20 * Math.PI) / 180, efficiency: 0.6, sampleBudget: 4000, quality: { maxError: 0.2 },
  },
};

/** Plans the spray warm-up's search (SPRAY_WARM_UP). */
function warmUpSpray(Mesh) {
  const dome = Mesh.fromStl(capStl(...SPRAY_WARM_UP.cap));
  try {
    dome.planSpray(SPRAY_WARM_UP.params).free();
  } finally {
    dome.free();
  }
}

/**
 * Runs the accurate geodesic method on a small cap (from its rim and from a plane section) and
 * a small sphere (from its south pole, with the focal point at the north pole).
 */
function warmUpGeodesics(Mesh) {
  const cap = Mesh.fromStl(capStl(24, 64, 1, 1000));
  try {
    cap.geodesicDistance({ boundaryOf: 'mesh' }, { method: 'accurate' }).free();
    cap.geodesicDistance({ plane: { point: [0, 0, 1000 * Math.cos(0.5)], normal: [0, 0, 1] } }, { method: 'accurate' }).free();
  } finally {
    cap.free();
  }
  const sphere = Mesh.fromStl(capStl(32, 64, Math.PI, 100));
  try {
    const z = sphere.positions();
    let south = 0;
    for (let v = 1; 3 * v < z.length; v++) if (z[3 * v + 2] < z[3 * south + 2]) south = v;
    sphere.geodesicDistance({ vertices: [south] }, { method: 'accurate' }).free();
  } finally {
    sphere.free();
  }
}

/**
 * The warm-up's steps, each about a tenth of a second: the worker runs one per idle second,
 * so a request that comes meanwhile waits for one step at most. Errors are the caller's to
 * report: the distances and the plan are known to work on these shapes, so one is a bug.
 */
export const WARM_UP_STEPS = [warmUpGeodesics, warmUpSpray];

/** Runs every step of the warm-up; returns the milliseconds it took. */
export function warmUp(Mesh) {
  const start = performance.now();
  for (const step of WARM_UP_STEPS) step(Mesh);
  return performance.now() - start;
}

/**
 * Bytes per triangle of the model that the accurate method's first distance grows the engine's
 * memory by at most, opened as in the page and warmed up (measured: 74–75 on the bench's caps
 * and spheres of 500k and 2M triangles, 100–112 on latitude–longitude caps of 200k–600k, 111
 * on the bench's 1M aircraft from a plane section). Small real models take more per triangle
 * (the wing-body sample, 80k triangles, grows by 18 MB: its sharp edges and small patches).
 */
export const FIRST_DISTANCE_BYTES_PER_TRIANGLE = 120;
/** The least reserved for a first distance, whatever the model (see above). */
export const FIRST_DISTANCE_LEAST_BYTES = 32 * 2 ** 20;

/**
 * Grows the engine's memory by what the Paths tool's first distance on a model of
 * `triangles` triangles will take (see `reserveMemory` in the engine): writing fresh memory
 * for the first time is about a seventh of that distance's time on a 500k-triangle panel,
 * paid here while the user sets up the source. `reserveMemory` is the engine's export.
 * Returns whether the memory could be had (nothing is lost when not: the distance grows it
 * as before).
 */
export function reserveFirstDistance(reserveMemory, triangles) {
  return reserveMemory(Math.max(FIRST_DISTANCE_LEAST_BYTES, FIRST_DISTANCE_BYTES_PER_TRIANGLE * triangles));
}
