// The 3D view: the only module that imports three.js.
// Tools draw their own results as layers (setLayer): line sets and unlit coloured surfaces
// in the file's frame, turned with the model; they never touch three.js themselves.
// The mesh comes as indexed chunks (at most 2^17 triangles each, made by the engine), its
// triangles grouped by patch (see worker.js), coloured per vertex. Visibility
// and highlighting only rewrite the chunks' draw groups (a handful of ranges), so they stay
// instant at millions of triangles. Nothing here walks the triangles: the worker sends the
// buffers, colours, per-patch boxes and the bounding sphere, and answers picks
// (setRayPicker) with the core's ray-cast index.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { patchColor } from './palette.js';

export { DROPPED_COLOR, PATCH_COLORS, patchColor } from './palette.js';

const BACKGROUND = 0xe9edf1;
/**
 * Bytes handed to WebGL in one animation frame at most (at least one chunk). WebGL copies a
 * chunk's buffers in one call on the first frame that draws it, and the page cannot go on
 * until the GPU process has taken them: 6 MB a frame kept every task short in headless
 * SwiftShader (4 million non-indexed triangles at once held the page for about 280 ms), and
 * with the engine's indexed chunks (about 1.5 MB each) one chunk a frame made the upload
 * wait on the frame rate (32 frames for 4M triangles).
 */
const FRAME_UPLOAD_BYTES = 6 * 1024 * 1024;
// Material slots of the draw groups. While a patch is selected the others are dimmed, so the
// selection stands out in its own, unchanged colour.
const BASE = 0;
const HOVER = 1;
const SELECTED = 2;
const DIM = 3;
const DIM_HOVER = 4;
// Standard views as directions from the target to the camera, in the display frame (Y up).
// The up-axis setting turns the model so that its up axis is the display's Y.
const VIEWS = {
  top: new THREE.Vector3(0, 1, 1e-4), // not exactly along Y: the orbit needs an azimuth
  front: new THREE.Vector3(0, 0, 1),
  side: new THREE.Vector3(1, 0, 0),
  iso: new THREE.Vector3(1, 0.8, 1),
};

function surfaceMaterial(emissiveIntensity, color = 0xffffff) {
  // Flat shading takes each face's normal from screen-space derivatives, so it always faces
  // the camera: lighting is right whatever the triangle's winding, with no normal buffer.
  return new THREE.MeshLambertMaterial({
    color, // multiplies the vertex colours
    vertexColors: true,
    flatShading: true,
    side: THREE.DoubleSide,
    emissive: 0xffffff,
    emissiveIntensity,
    // Push faces back a little so that border lines on them are not hidden.
    polygonOffset: true,
    polygonOffsetFactor: 1,
    polygonOffsetUnits: 1,
  });
}

/**
 * Marks point `p` for a 'lines' layer: three segments along the axes, `size` either side of
 * it, pushed onto `positions` (x y z, two points per segment); seen from any side as a cross.
 */
export function pointMark(positions, p, size) {
  for (let k = 0; k < 3; k++) {
    const a = [...p];
    const b = [...p];
    a[k] -= size;
    b[k] += size;
    positions.push(...a, ...b);
  }
}

export class Viewer extends EventTarget {
  #container;
  #renderer;
  #scene = new THREE.Scene();
  #camera = new THREE.PerspectiveCamera(40, 1, 0.01, 1000);
  #controls;
  #model = new THREE.Group(); // turned by the up-axis setting
  #surface = null; // Group of the chunk meshes of the model
  #chunks = []; // chunk meshes, each with userData { start, end } in triangles
  #pendingChunks = []; // chunks not yet in the scene (see #feedChunks)
  #fence = null; // WebGLSync after the last chunk's upload, or after the previous model
  #feedToken = 0; // bumped by setModel: an older model's #feedChunks loop stops
  #drawnWaiters = []; // resolve functions of drawn() promises
  #sphere = new THREE.Sphere(); // bounding sphere of the model, file frame
  #warmObjects = []; // keep the programs compiled at start-up cached (see #warmUpPrograms)
  #borders = null;
  #materials = [surfaceMaterial(0), surfaceMaterial(0.14), surfaceMaterial(0.06),
    surfaceMaterial(0, 0x8c8c8c), surfaceMaterial(0.14, 0x8c8c8c)];
  #borderMaterial = new THREE.LineBasicMaterial({ color: 0x15191d, transparent: true, opacity: 0.75 });
  #ranges = new Uint32Array(0);
  #state = { hidden: new Set(), selected: null, hovered: null, showBorders: true };
  #borderPatches = new Int32Array(0); // two patch ids per border segment
  #borderHiddenKey = '';
  #boxes = new Float32Array(0); // per bucket: min xyz, max xyz
  #rayPicker = null; // see setRayPicker
  #raycaster = new THREE.Raycaster();
  #renderQueued = false;
  #sceneRadius = 1; // bounding radius of the whole model: bounds the far plane
  #gizmo;
  #layers = new Map(); // tool layer id -> three.js object

  constructor(container) {
    super();
    this.#container = container;
    // Throws when WebGL is unavailable; the page reports it.
    this.#renderer = new THREE.WebGLRenderer({ antialias: true, powerPreference: 'high-performance' });
    this.#renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
    this.#renderer.setClearColor(BACKGROUND);
    this.#renderer.autoClear = false;
    const canvas = this.#renderer.domElement;
    canvas.setAttribute('role', 'img');
    canvas.setAttribute('aria-label', '3D view of the model, coloured by patch. Arrow keys pan when focused.');
    canvas.tabIndex = 0;
    container.appendChild(canvas);

    this.#scene.add(this.#model);
    this.#scene.add(new THREE.HemisphereLight(0xffffff, 0x8a96a3, 1.6));
    // A headlight that follows the camera, slightly above and to the left of the eye.
    const headlight = new THREE.DirectionalLight(0xffffff, 2.0);
    headlight.position.set(-0.3, 0.5, 1);
    headlight.target.position.set(0, 0, -1);
    this.#camera.add(headlight, headlight.target);
    this.#scene.add(this.#camera);

    this.#controls = new OrbitControls(this.#camera, canvas);
    this.#controls.zoomToCursor = true;
    this.#controls.screenSpacePanning = true;
    this.#controls.addEventListener('change', () => this.#onCameraChange());
    this.#controls.listenToKeyEvents(canvas); // arrow keys pan while the view has focus
    this.#gizmo = new AxisGizmo();
    this.#warmUpPrograms();

    new ResizeObserver(() => this.#resize()).observe(container);
    this.#resize();
    this.#listenForPicks(canvas);
    canvas.addEventListener('webglcontextlost', (event) => event.preventDefault());
    canvas.addEventListener('webglcontextrestored', () => {
      // The model's arrays were let go once on the GPU: ask for them again ('modellost').
      if (this.#surface) {
        this.#disposeModel();
        this.dispatchEvent(new CustomEvent('modellost'));
      }
      this.requestRender();
    });
  }

  get canvas() {
    return this.#renderer.domElement;
  }

  /**
   * Picking goes through `fn(origin, direction, hidden, { click })` → Promise of { patchId,
   * point } or null: the ray in the model's coordinates (file frame, direction not
   * normalised), the hidden patch ids (-1 = dropped), which the ray passes through, and
   * whether a click (rather than a hover) asks.
   */
  setRayPicker(fn) {
    this.#rayPicker = fn;
  }

  /**
   * Shows a mesh: display = { positions, indices, chunks, colors, ranges, boxes, sphere,
   * borders, borderPatches } from the worker (file frame; see worker.js). The arrays are used,
   * not copied, and the positions, indices and colours are let go once on the GPU. WebGL
   * copies a chunk's buffers in one call on the first frame that draws it, and the page
   * cannot go on until the GPU process has taken them, so chunks join the scene one at a
   * time, each once the GPU has finished all earlier work (a fence). `keepView` keeps the
   * camera (re-segmenting the same model); otherwise the view is fitted. Emits 'modellost'
   * when a lost WebGL context comes back: the caller then sets the model again.
   */
  setModel(display, { keepView = false } = {}) {
    this.#disposeModel();
    const { positions, indices, chunks, colors, ranges, boxes, sphere, borders, borderPatches } = display;
    this.#ranges = ranges;
    this.#boxes = boxes;
    this.#borderPatches = borderPatches;
    this.#borderHiddenKey = '';

    this.#sphere = new THREE.Sphere(new THREE.Vector3(sphere[0], sphere[1], sphere[2]), sphere[3]);
    this.#sceneRadius = Math.max(sphere[3], 1e-9);
    this.#surface = new THREE.Group();
    for (let c = 0; c < chunks.length; c += 4) {
      const [start, count, firstVertex, vertices] = chunks.subarray(c, c + 4);
      const end = start + count;
      const [v0, v1] = [3 * firstVertex, 3 * (firstVertex + vertices)];
      // Views into the worker's arrays, not copies, let go once WebGL has them: nothing here
      // reads them again (boxes, sphere and picks come from the worker).
      const geometry = new THREE.BufferGeometry();
      const index = new THREE.BufferAttribute(indices.subarray(3 * start, 3 * end), 1);
      const position = new THREE.BufferAttribute(positions.subarray(v0, v1), 3);
      const color = new THREE.BufferAttribute(colors.subarray(v0, v1), 3, true);
      geometry.setIndex(index.onUpload(releaseArray));
      geometry.setAttribute('position', position.onUpload(releaseArray));
      geometry.setAttribute('color', color.onUpload(releaseArray));
      geometry.boundingSphere = this.#sphere; // the whole model's: culling stays conservative
      const chunk = new THREE.Mesh(geometry, this.#materials);
      chunk.raycast = () => {}; // picking goes to the worker, never three's brute force
      chunk.userData = { start, end };
      this.#chunks.push(chunk);
    }
    this.#pendingChunks = [...this.#chunks];
    this.#model.add(this.#surface);
    this.#fenceGpu(); // the first chunk waits until the GPU is done with the previous model
    const token = ++this.#feedToken;
    requestAnimationFrame(() => this.#feedChunks(token));

    const lineGeometry = new THREE.BufferGeometry();
    lineGeometry.setAttribute('position', new THREE.BufferAttribute(borders, 3));
    this.#borders = new THREE.LineSegments(lineGeometry, this.#borderMaterial);
    this.#borders.raycast = () => {};
    this.#model.add(this.#borders);

    this.#state.hidden = new Set();
    this.#state.selected = null;
    this.#state.hovered = null;
    this.#applyState();
    if (!keepView) this.fit(VIEWS.iso);
    this.requestRender();
  }

  /** Resolves once the model on screen is wholly in WebGL (at once when nothing is pending). */
  drawn() {
    if (!this.#pendingChunks.length) return Promise.resolve();
    return new Promise((resolve) => this.#drawnWaiters.push(resolve));
  }

  #resolveDrawn() {
    const waiters = this.#drawnWaiters;
    this.#drawnWaiters = [];
    for (const resolve of waiters) resolve();
  }

  /** Updates what is drawn: { hidden: Set<id> (-1 = dropped), selected, hovered, showBorders }. */
  setPatchState(state) {
    Object.assign(this.#state, state);
    this.#applyState();
    this.requestRender();
  }

  /** 'y' or 'z': which axis of the file points up on screen. */
  setUpAxis(axis) {
    this.#model.rotation.set(axis === 'z' ? -Math.PI / 2 : 0, 0, 0);
    this.#model.updateMatrixWorld(true);
    this.#gizmo.setUpAxis(axis);
    if (this.#surface) this.fit(this.#viewDirection());
    this.requestRender();
  }

  /** Standard view: 'fit' (keep the direction), 'top', 'front', 'side' or 'iso'. */
  setView(name) {
    this.fit(name === 'fit' ? this.#viewDirection() : VIEWS[name]);
  }

  /** Frames the visible model, looking along `direction` (target → camera). */
  fit(direction = this.#viewDirection()) {
    if (!this.#surface) return;
    const sphere = this.#sphere.clone().applyMatrix4(this.#surface.matrixWorld);
    this.#frameSphere(sphere, direction);
  }

  /**
   * Frames one patch (its bounding box comes from the worker), looking from `normal` (file
   * frame, e.g. the patch's mean normal) when given.
   */
  fitPatch(id, normal = null) {
    if (!this.#surface || id === null || id < 0 || 6 * id + 6 > this.#boxes.length) return;
    const b = this.#boxes.subarray(6 * id, 6 * id + 6);
    if (!(b[0] <= b[3])) return; // an empty patch
    const box = new THREE.Box3(new THREE.Vector3(b[0], b[1], b[2]), new THREE.Vector3(b[3], b[4], b[5]));
    const sphere = box.getBoundingSphere(new THREE.Sphere()).applyMatrix4(this.#surface.matrixWorld);
    let direction = this.#viewDirection();
    if (normal) {
      // Slightly off the normal, so that the surface's relief still shows.
      direction = new THREE.Vector3(...normal).applyQuaternion(this.#model.quaternion).normalize()
        .addScaledVector(direction.normalize(), 0.35);
    }
    this.#frameSphere(sphere, direction);
  }

  /**
   * Adds or replaces a tool's layer (ids are namespaced by tool, e.g. 'spray.path'):
   *   { kind: 'lines', positions: Float32Array (x y z, two points per segment),
   *     colors?: Uint8Array (sRGB r g b per point) or color?: '#rrggbb', dashed?: boolean,
   *     dashSize?: number (file units) }
   *   { kind: 'surface', positions: Float32Array, indices: Uint32Array,
   *     colors: Uint8Array (sRGB r g b per vertex) }   drawn unlit, so it shows the exact colours
   * The arrays are kept (not copied): the caller must not change them afterwards.
   */
  setLayer(id, spec) {
    this.removeLayer(id);
    const object = layerObject(spec);
    this.#layers.set(id, object);
    this.#model.add(object);
    this.requestRender();
  }

  /** Removes a layer (no-op for an unknown id). */
  removeLayer(id) {
    const object = this.#layers.get(id);
    if (!object) return;
    this.#model.remove(object);
    object.geometry.dispose();
    object.material.dispose();
    this.#layers.delete(id);
    this.requestRender();
  }

  /** Shows or hides a layer without rebuilding it. */
  setLayerVisible(id, visible) {
    const object = this.#layers.get(id);
    if (!object || object.visible === visible) return;
    object.visible = visible;
    this.requestRender();
  }

  /** Drops the model (the view goes empty). */
  clear() {
    this.#disposeModel();
    this.requestRender();
  }

  requestRender() {
    if (this.#renderQueued) return;
    this.#renderQueued = true;
    requestAnimationFrame(() => {
      this.#renderQueued = false;
      this.#render();
    });
  }

  /**
   * Compiles and links, once at start-up, the shader program of every kind of object the
   * view draws (model, borders, each kind of layer). Checking a program's link status makes
   * the page wait until the GPU has finished all the work queued before it, which on a
   * software GPU drawing millions of triangles takes seconds; a program first needed later
   * (a tool's first layer) would freeze the page that long. The objects stay referenced so
   * that their programs stay in three.js's cache.
   */
  #warmUpPrograms() {
    const three = new Float32Array([0, 0, 0, 1e-6, 0, 0, 0, 1e-6, 0]);
    const rgb = new Uint8Array(9);
    const lines = new THREE.BufferGeometry().setAttribute('position', new THREE.BufferAttribute(three.slice(0, 6), 3));
    const surface = new THREE.BufferGeometry()
      .setAttribute('position', new THREE.BufferAttribute(three, 3))
      .setAttribute('color', new THREE.BufferAttribute(rgb, 3, true));
    const objects = [
      ...this.#materials.map((m) => new THREE.Mesh(surface, m)),
      new THREE.LineSegments(lines, this.#borderMaterial),
      ...[false, true].flatMap((dashed) => [
        layerObject({ kind: 'lines', positions: three.slice(0, 6), color: '#000000', dashed }),
        layerObject({ kind: 'lines', positions: three.slice(0, 6), colors: rgb.slice(0, 6), dashed }),
      ]),
      layerObject({ kind: 'surface', positions: three, indices: new Uint32Array([0, 1, 2]), colors: rgb }),
    ];
    for (const object of objects) object.frustumCulled = false;
    this.#warmObjects = objects;
    this.#model.add(...objects);
    this.#render();
    this.#model.remove(...objects);
  }

  /** Puts a fence after the GPU work queued so far (replacing any earlier fence). */
  #fenceGpu() {
    const gl = this.#renderer.getContext();
    if (this.#fence) gl.deleteSync(this.#fence);
    this.#fence = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl.flush();
  }

  /**
   * Hands the model to WebGL a few chunks per animation frame (FRAME_UPLOAD_BYTES), each
   * frame's only once the GPU has finished everything queued before (polling the fence does
   * not wait), so that the copy
   * never queues behind drawing, which a software GPU does slowly. No chunk is drawn until
   * all are in (#applyState), so nothing but the copies keeps the GPU busy meanwhile.
   */
  #feedChunks(token) {
    if (token !== this.#feedToken || !this.#pendingChunks.length) return;
    const gl = this.#renderer.getContext();
    const next = () => requestAnimationFrame(() => this.#feedChunks(token));
    if (this.#fence && !gl.isContextLost() && gl.getSyncParameter(this.#fence, gl.SYNC_STATUS) !== gl.SIGNALED) {
      next();
      return;
    }
    // Chunks up to the frame's budget of bytes, at least one.
    let bytes = 0;
    do {
      const chunk = this.#pendingChunks.shift();
      bytes += uploadBytes(chunk.geometry);
      this.#surface.add(chunk);
    } while (this.#pendingChunks.length && bytes + uploadBytes(this.#pendingChunks[0].geometry) <= FRAME_UPLOAD_BYTES);
    if (this.#pendingChunks.length) {
      this.#render(); // uploads the chunk
      this.#fenceGpu();
      next();
    } else {
      if (this.#fence) gl.deleteSync(this.#fence);
      this.#fence = null;
      this.#applyState();
      this.requestRender();
      this.#resolveDrawn();
    }
  }

  #render() {
    const renderer = this.#renderer;
    renderer.clear();
    renderer.render(this.#scene, this.#camera);
    this.#gizmo.render(renderer, this.#camera);
  }

  #isVisible(id) {
    return !this.#state.hidden.has(id < 0 ? -1 : id);
  }

  /**
   * Rebuilds each chunk's draw groups: the visible buckets' triangles within the chunk,
   * consecutive ones with equal looks merged. O(chunks × patches).
   */
  #applyState() {
    if (!this.#surface) return;
    const { selected, hovered, showBorders } = this.#state;
    const buckets = this.#ranges.length / 2;
    for (const chunk of this.#chunks) {
      const { start, end } = chunk.userData;
      const geometry = chunk.geometry;
      geometry.clearGroups();
      if (this.#pendingChunks.length) continue; // drawn once every chunk is on the GPU
      let open = null;
      for (let b = 0; b < buckets; b++) {
        const id = b === buckets - 1 ? -1 : b;
        const first = Math.max(start, this.#ranges[2 * b]);
        const last = Math.min(end, this.#ranges[2 * b] + this.#ranges[2 * b + 1]);
        if (last <= first || !this.#isVisible(id)) {
          open = null;
          continue;
        }
        const dim = selected !== null && id !== selected;
        const hover = id === hovered && id >= 0;
        const material = id === selected ? SELECTED : dim ? (hover ? DIM_HOVER : DIM) : hover ? HOVER : BASE;
        const groupStart = 3 * (first - start);
        if (open && open.materialIndex === material && open.start + open.count === groupStart) {
          open.count += 3 * (last - first);
        } else {
          open = { start: groupStart, count: 3 * (last - first), materialIndex: material };
          geometry.groups.push(open);
        }
      }
    }
    this.#applyBorderState(showBorders);
  }

  /** Border lines of hidden patches would float in the air: draw only those of visible ones. */
  #applyBorderState(showBorders) {
    const hidden = this.#state.hidden;
    const sides = this.#borderPatches;
    this.#borders.visible = showBorders;
    const key = [...hidden].sort((a, b) => a - b).join(',');
    if (key === this.#borderHiddenKey) return;
    this.#borderHiddenKey = key;
    const geometry = this.#borders.geometry;
    if (!hidden.size) {
      geometry.setIndex(null);
      return;
    }
    // A segment stays while the patch on either side of it is visible.
    const visible = [];
    for (let s = 0; s < sides.length / 2; s++) {
      if (this.#isVisible(sides[2 * s]) || this.#isVisible(sides[2 * s + 1])) visible.push(2 * s, 2 * s + 1);
    }
    geometry.setIndex(visible);
  }

  #disposeModel() {
    if (this.#surface) {
      this.#model.remove(this.#surface, this.#borders);
      for (const chunk of this.#chunks) chunk.geometry.dispose(); // frees the GPU buffers
      this.#borders.geometry.dispose();
      this.#surface = null;
      this.#borders = null;
    }
    this.#chunks = [];
    this.#pendingChunks = [];
    this.#resolveDrawn();
    this.#ranges = new Uint32Array(0);
    this.#boxes = new Float32Array(0);
    this.#borderPatches = new Int32Array(0);
  }

  /** Unit direction the camera looks along, in the model's coordinates (file axes). */
  viewDirectionInModel() {
    const d = this.#controls.target.clone().sub(this.#camera.position);
    if (d.lengthSq() === 0) return [0, 0, -1];
    d.applyQuaternion(this.#model.quaternion.clone().invert()).normalize();
    return [d.x, d.y, d.z];
  }

  #viewDirection() {
    return this.#camera.position.clone().sub(this.#controls.target);
  }

  #frameSphere(sphere, direction) {
    const radius = Math.max(sphere.radius, 1e-9);
    const fov = THREE.MathUtils.degToRad(this.#camera.fov);
    const fitFov = this.#camera.aspect < 1 ? 2 * Math.atan(Math.tan(fov / 2) * this.#camera.aspect) : fov;
    const distance = (radius / Math.sin(fitFov / 2)) * 1.05;
    const dir = direction.clone();
    if (dir.lengthSq() === 0) dir.copy(VIEWS.iso);
    dir.normalize();
    this.#controls.target.copy(sphere.center);
    this.#camera.position.copy(sphere.center).addScaledVector(dir, distance);
    this.#controls.update();
    this.#onCameraChange();
  }

  #onCameraChange() {
    // Near and far follow the zoom: depth precision at any scale, from millimetres to a wing.
    const distance = this.#camera.position.distanceTo(this.#controls.target);
    this.#camera.near = Math.max(distance * 0.002, this.#sceneRadius * 1e-6);
    this.#camera.far = distance + 4 * this.#sceneRadius;
    this.#camera.updateProjectionMatrix();
    this.requestRender();
  }

  #resize() {
    const width = Math.max(1, this.#container.clientWidth);
    const height = Math.max(1, this.#container.clientHeight);
    this.#renderer.setSize(width, height, false);
    this.#camera.aspect = width / height;
    this.#camera.updateProjectionMatrix();
    this.requestRender();
  }

  /** The patch under a point of the canvas: Promise of { patchId, point } or null (a miss). */
  async #pickAt(clientX, clientY, click = false) {
    if (!this.#surface || !this.#rayPicker) return null;
    const rect = this.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    this.#raycaster.setFromCamera(ndc, this.#camera);
    const surface = this.#surface;
    const toModel = surface.matrixWorld.clone().invert();
    const ray = this.#raycaster.ray.clone().applyMatrix4(toModel);
    const hit = await this.#rayPicker(ray.origin.toArray(), ray.direction.toArray(), [...this.#state.hidden], { click });
    return surface === this.#surface ? hit : null; // the model was replaced meanwhile
  }

  /**
   * Emits 'hover' { patchId | null, clientX, clientY } and 'pick' { patchId | null, point }
   * (point: the hit in the model's coordinates, null on a miss). Picks are answered by the
   * worker: hovers keep one request in flight and answer the latest pointer position only;
   * clicks are answered in order.
   */
  #listenForPicks(canvas) {
    let down = null;
    let hoverAt = null; // latest pointer position not yet asked about
    let hoverBusy = false;
    let hoverEpoch = 0; // bumped when the pointer leaves: late answers are dropped
    const emit = (type, detail) => this.dispatchEvent(new CustomEvent(type, { detail }));
    const hoverLoop = async () => {
      hoverBusy = true;
      try {
        while (hoverAt) {
          const { x, y } = hoverAt;
          const epoch = hoverEpoch;
          hoverAt = null;
          const hit = await this.#pickAt(x, y);
          if (hoverAt === null && epoch === hoverEpoch) emit('hover', { patchId: hit ? hit.patchId : null, clientX: x, clientY: y });
        }
      } finally {
        hoverBusy = false;
      }
    };
    canvas.addEventListener('pointermove', (event) => {
      if (event.buttons !== 0) return; // orbiting, not hovering
      hoverAt = { x: event.clientX, y: event.clientY };
      if (!hoverBusy) hoverLoop();
    });
    canvas.addEventListener('pointerleave', () => {
      hoverAt = null;
      hoverEpoch++;
      emit('hover', { patchId: null });
    });
    canvas.addEventListener('pointerdown', (event) => {
      down = { x: event.clientX, y: event.clientY, time: performance.now(), button: event.button };
    });
    canvas.addEventListener('pointerup', async (event) => {
      // A click, not the end of an orbit: little movement, short press, primary button.
      if (!down || down.button !== 0) return;
      const moved = Math.hypot(event.clientX - down.x, event.clientY - down.y);
      if (moved > 4 || performance.now() - down.time > 600) return;
      const hit = await this.#pickAt(event.clientX, event.clientY, true);
      emit('pick', { patchId: hit ? hit.patchId : null, point: hit ? hit.point : null });
    });
    canvas.addEventListener('dblclick', async (event) => {
      const hit = await this.#pickAt(event.clientX, event.clientY, true);
      if (hit && hit.patchId >= 0) this.fitPatch(hit.patchId);
    });
  }
}

/** Small axis triad in the lower-left corner, turned with the model, labelled X Y Z. */
class AxisGizmo {
  #scene = new THREE.Scene();
  #camera = new THREE.OrthographicCamera(-1.6, 1.6, 1.6, -1.6, 0.1, 10);
  #axes = new THREE.Group();
  #size = 96;

  constructor() {
    const colors = ['#d62728', '#2ca02c', '#1f77b4'];
    ['X', 'Y', 'Z'].forEach((label, i) => {
      const dir = new THREE.Vector3().setComponent(i, 1);
      const line = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), dir]);
      this.#axes.add(new THREE.Line(line, new THREE.LineBasicMaterial({ color: colors[i] })));
      const sprite = new THREE.Sprite(new THREE.SpriteMaterial({ map: labelTexture(label, colors[i]), depthTest: false }));
      sprite.position.copy(dir).multiplyScalar(1.3);
      sprite.scale.setScalar(0.55);
      this.#axes.add(sprite);
    });
    this.#scene.add(this.#axes);
  }

  setUpAxis(axis) {
    this.#axes.rotation.set(axis === 'z' ? -Math.PI / 2 : 0, 0, 0);
  }

  render(renderer, mainCamera) {
    // Same orientation as the main camera, fixed distance.
    this.#camera.position.set(0, 0, 4).applyQuaternion(mainCamera.quaternion);
    this.#camera.quaternion.copy(mainCamera.quaternion);
    const size = this.#size;
    renderer.setViewport(0, 0, size, size);
    renderer.setScissor(0, 0, size, size);
    renderer.setScissorTest(true);
    renderer.clearDepth();
    renderer.render(this.#scene, this.#camera);
    renderer.setScissorTest(false);
    const canvas = renderer.domElement;
    renderer.setViewport(0, 0, canvas.width / renderer.getPixelRatio(), canvas.height / renderer.getPixelRatio());
  }
}

/** Bytes of a geometry's index and attributes not yet handed to WebGL. */
function uploadBytes(geometry) {
  let bytes = geometry.index?.array?.byteLength ?? 0;
  for (const attribute of Object.values(geometry.attributes)) bytes += attribute.array?.byteLength ?? 0;
  return bytes;
}

/** BufferAttribute.onUpload callback: the GPU has the data, the page needs no copy. */
function releaseArray() {
  this.array = null;
}

/** A tool layer's three.js object (see Viewer.setLayer). */
function layerObject(spec) {
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(spec.positions, 3));
  if (spec.colors) geometry.setAttribute('color', new THREE.BufferAttribute(linearColors(spec.colors), 3));
  let object;
  if (spec.kind === 'surface') {
    geometry.setIndex(new THREE.BufferAttribute(spec.indices, 1));
    object = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide }));
  } else {
    const common = { vertexColors: Boolean(spec.colors), color: spec.colors ? 0xffffff : spec.color ?? '#000000' };
    const material = spec.dashed
      ? new THREE.LineDashedMaterial({ ...common, dashSize: spec.dashSize ?? 1, gapSize: spec.dashSize ?? 1 })
      : new THREE.LineBasicMaterial(common);
    object = new THREE.LineSegments(geometry, material);
    if (spec.dashed) object.computeLineDistances();
  }
  object.raycast = () => {}; // picking stays on the model's patches
  object.renderOrder = spec.kind === 'surface' ? 1 : 2;
  return object;
}

/** sRGB bytes to linear floats: the renderer encodes back to sRGB, so the screen shows the bytes. */
const SRGB_TO_LINEAR = Float32Array.from({ length: 256 }, (_, i) => {
  const c = i / 255;
  return c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055) ** 2.4;
});
function linearColors(bytes) {
  const out = new Float32Array(bytes.length);
  for (let i = 0; i < bytes.length; i++) out[i] = SRGB_TO_LINEAR[bytes[i]];
  return out;
}

function labelTexture(text, color) {
  const canvas = document.createElement('canvas');
  canvas.width = 64;
  canvas.height = 64;
  const ctx = canvas.getContext('2d');
  ctx.font = 'bold 44px system-ui, sans-serif';
  ctx.fillStyle = color;
  ctx.textAlign = 'center';
  ctx.textBaseline = 'middle';
  ctx.fillText(text, 32, 34);
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}
