// Hover and click picking of patches: a three-mesh-bvh BVH over the display triangles.
// Indirect mode keeps the triangle order (sorted by patch) untouched, so a hit's faceIndex
// maps straight to a patch through the ranges. The BVH is built on first use, not on load,
// so that a large model shows before picking is ready.
import { BufferGeometry, DoubleSide, Matrix4, Ray } from 'three';
import { MeshBVH } from 'three-mesh-bvh';

export class PatchPicker {
  #bvh = null;
  #position = null;
  #starts = null; // first triangle of each bucket (patches, then the dropped bucket)
  #inverse = new Matrix4();
  #ray = new Ray();

  /** position: the display geometry's attribute; ranges: [start, count] per bucket. */
  setGeometry(position, ranges) {
    this.#bvh = null;
    this.#position = position;
    this.#starts = ranges.filter((_, i) => i % 2 === 0);
  }

  clear() {
    this.#bvh = null;
    this.#position = null;
    this.#starts = null;
  }

  /** Patch id of a display triangle; -1 for a dropped triangle. */
  patchOfTriangle(triangle) {
    const starts = this.#starts;
    let lo = 0;
    let hi = starts.length - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (starts[mid] <= triangle) lo = mid;
      else hi = mid - 1;
    }
    return lo === starts.length - 1 ? -1 : lo;
  }

  /** Builds the BVH now (idempotent; a no-op once the geometry is gone). */
  prepare() {
    if (this.#bvh || !this.#position) return;
    // A group-free geometry sharing the positions: groups change with visibility, and
    // a BVH built over groups would only cover the triangles visible at build time.
    const geometry = new BufferGeometry();
    geometry.setAttribute('position', this.#position);
    this.#bvh = new MeshBVH(geometry, { indirect: true });
  }

  /**
   * Nearest hit along the raycaster's ray on a visible bucket of `object`:
   * { patchId, point } (-1 = dropped triangle; point [x, y, z] in the model's own
   * coordinates) or null when nothing visible is hit.
   */
  pick(raycaster, object, isVisible) {
    if (!this.#position) return null;
    this.prepare();
    this.#inverse.copy(object.matrixWorld).invert();
    this.#ray.copy(raycaster.ray).applyMatrix4(this.#inverse);
    const hits = this.#bvh.raycast(this.#ray, DoubleSide);
    hits.sort((a, b) => a.distance - b.distance);
    for (const hit of hits) {
      const patchId = this.patchOfTriangle(hit.faceIndex);
      if (isVisible(patchId)) return { patchId, point: [hit.point.x, hit.point.y, hit.point.z] };
    }
    return null;
  }
}
