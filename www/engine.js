// The page's side of the wasm core. Heavy work (parsing, segmentation, export) runs in a
// module worker that keeps the parsed Mesh alive between requests; the main thread loads
// the same package only for deriveThreshold(), which is cheap and must answer while the
// worker is busy (live threshold display as the user types).
//
// Worker protocol (main.js sends one request at a time; ids tie replies to requests):
//   page → worker  { id, op: 'open', buffer, name, params }   the file's ArrayBuffer is transferred
//                  { id, op: 'segment', params }
//                  { id, op: 'patchStl', patchId }
//                  { id, op: 'zip', names: [{ patchId, fileName }] }
//   worker → page  { type: 'ready' } | { type: 'fatal', message }     once, after wasm init
//                  { id, type: 'progress', stage, fraction }           any number, then
//                  { id, type: 'done', result }                        either this
//                  { id, type: 'error', message, broken }              or this
// Results carry typed arrays whose buffers are transferred back. `broken` means the wasm
// instance may be corrupt (a trap or out of memory): the engine then replaces the worker,
// which drops the mesh it held (hasMesh turns false). Cancel also replaces the worker.
import init, { deriveThreshold as coreDeriveThreshold } from './pkg/skinpath.js';

/** Raised for requests abandoned by cancel(); callers treat it as "nothing happened". */
export class CancelledError extends Error {
  constructor() {
    super('cancelled');
    this.name = 'CancelledError';
  }
}

export class Engine {
  #worker = null;
  #pending = new Map(); // id -> { resolve, reject, onProgress }
  #nextId = 1;
  #ready = null;

  /** True while the worker holds a parsed mesh that segment() can use. */
  hasMesh = false;

  /** Loads the wasm package here and in a fresh worker; rejects with a readable message. */
  async start() {
    await init();
    this.#spawn();
    await this.#ready;
  }

  /** Live, synchronous threshold: { kind: 'angle'|'curvature', value }; throws Error. */
  deriveThreshold(params) {
    return coreDeriveThreshold(params);
  }

  /**
   * Parses an STL (the buffer is transferred, so the caller loses it) and, when params are
   * given, segments it. Resolves to { report, triangleCount, vertexCount, memoryBytes,
   * display, segmentation | null, segmentError | null, timings }.
   */
  async open(buffer, name, params, onProgress) {
    const result = await this.#request({ op: 'open', buffer, name, params }, [buffer], onProgress);
    this.hasMesh = true;
    return result;
  }

  /** Re-segments the mesh the worker holds. Resolves like open() minus report. */
  segment(params, onProgress) {
    return this.#request({ op: 'segment', params }, [], onProgress);
  }

  /** Binary STL of one patch of the current segmentation, as a Uint8Array. */
  patchStl(patchId) {
    return this.#request({ op: 'patchStl', patchId }, []);
  }

  /** Zip archive (Uint8Array) with one binary STL per patch; names: [{ patchId, fileName }]. */
  zipPatches(names, onProgress) {
    return this.#request({ op: 'zip', names }, [], onProgress);
  }

  /** Stops the running request at once by replacing the worker. The mesh is lost with it. */
  cancel() {
    this.#restart(new CancelledError());
  }

  #spawn() {
    const worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module', name: 'skinpath-engine' });
    this.#worker = worker;
    this.hasMesh = false;
    this.#ready = new Promise((resolve, reject) => {
      worker.addEventListener('message', (event) => {
        const msg = event.data;
        if (msg.type === 'ready') resolve();
        else if (msg.type === 'fatal') reject(new Error(msg.message));
        else this.#onMessage(msg);
      });
      // Script load failures and uncaught exceptions: nothing in flight can finish.
      worker.addEventListener('error', (event) => {
        event.preventDefault();
        const error = new Error('The processing engine stopped unexpectedly. The model on screen is unchanged; please try again.');
        reject(error);
        if (this.#worker === worker) this.#restart(error);
      });
    });
    // Avoid an unhandled rejection when nobody awaits a later respawn's readiness.
    this.#ready.catch(() => {});
  }

  #restart(reason) {
    this.#worker?.terminate();
    const pending = [...this.#pending.values()];
    this.#pending.clear();
    this.#spawn();
    for (const p of pending) p.reject(reason);
  }

  #onMessage(msg) {
    const p = this.#pending.get(msg.id);
    if (!p) return; // a reply to a request that was cancelled meanwhile
    if (msg.type === 'progress') {
      p.onProgress?.(msg.stage, msg.fraction);
    } else if (msg.type === 'done') {
      this.#pending.delete(msg.id);
      p.resolve(msg.result);
    } else if (msg.type === 'error') {
      this.#pending.delete(msg.id);
      if (msg.broken) this.#restart(new CancelledError());
      p.reject(new Error(msg.message));
    }
  }

  async #request(message, transfer, onProgress) {
    await this.#ready;
    const id = this.#nextId++;
    return new Promise((resolve, reject) => {
      this.#pending.set(id, { resolve, reject, onProgress });
      this.#worker.postMessage({ id, ...message }, transfer);
    });
  }
}
