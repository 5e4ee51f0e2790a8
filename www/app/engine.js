// The page's side of the wasm core: a channel to the module worker (worker/worker.js), which
// keeps the parsed Mesh alive between requests. The main thread loads the same package only
// for deriveThreshold(), which is cheap and must answer while the worker is busy.
//
// Requests: `request(op, payload, { transfer, onProgress, signal })` → Promise of the result.
//   op is 'open' or '<tool>.<name>' (handled by worker/<tool>.js); see worker.js for the
//   message format. Progress arrives as onProgress(stage, fraction). Errors reject with an
//   Error whose message is for the user. A running request cannot be interrupted inside
//   wasm, so cancel() and an aborted `signal` replace the worker: every pending request
//   rejects (CancelledError, or the signal's reason) and the new worker holds no mesh
//   (hasMesh turns false; the shell gives it the model again when a tool needs it).
import init, { deriveThreshold as coreDeriveThreshold } from '../pkg/skinpath.js';

/** Raised for requests abandoned by cancel(); callers treat it as "nothing happened". */
export class CancelledError extends Error {
  constructor(message = 'cancelled') {
    super(message);
    this.name = 'CancelledError';
  }
}

export class Engine {
  #worker = null;
  #pending = new Map(); // id -> { resolve, reject, onProgress }
  #nextId = 1;
  #ready = null;

  /** True while the worker holds a parsed mesh. */
  hasMesh = false;
  /** True once the wasm package is loaded on this thread (deriveThreshold works). */
  started = false;

  /** Loads the wasm package here and in a fresh worker; rejects with a readable message. */
  async start() {
    await init();
    this.started = true;
    this.#spawn();
    await this.#ready;
  }

  /** Live, synchronous threshold: { kind: 'angle'|'curvature', value }; throws Error. */
  deriveThreshold(params) {
    return coreDeriveThreshold(params);
  }

  /**
   * Parses an STL: `input` is { file } (a File, which the worker reads as a stream, never
   * whole) or { buffer } (an ArrayBuffer, transferred, so the caller loses it); `tools` holds
   * the params of tools that work right after parsing ({ segment: params }). Resolves to
   * { report, triangleCount, vertexCount, memoryBytes, display, tools: { segment: … }, timings }.
   */
  async open(input, name, tools, onProgress, signal) {
    this.hasMesh = false;
    const { file, buffer } = input;
    const result = await this.request('open', { file, buffer, name, tools },
      { transfer: buffer ? [buffer] : [], onProgress, signal });
    this.hasMesh = true;
    return result;
  }

  /** One request to a tool's worker module; see the header. */
  async request(op, payload = {}, { transfer = [], onProgress, signal } = {}) {
    await this.#ready;
    signal?.throwIfAborted();
    const id = this.#nextId++;
    return new Promise((resolve, reject) => {
      const onAbort = () => {
        if (this.#pending.has(id)) this.#restart(new CancelledError(), { [id]: signal.reason });
      };
      signal?.addEventListener('abort', onAbort, { once: true });
      const done = (fn) => (value) => {
        signal?.removeEventListener('abort', onAbort);
        fn(value);
      };
      this.#pending.set(id, { resolve: done(resolve), reject: done(reject), onProgress });
      this.#worker.postMessage({ id, op, ...payload }, transfer);
    });
  }

  /** Stops the running request at once by replacing the worker. The mesh is lost with it. */
  cancel() {
    this.#restart(new CancelledError());
  }

  #spawn() {
    const worker = new Worker(new URL('../worker/worker.js', import.meta.url), { type: 'module', name: 'skinpath-engine' });
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

  /** Replaces the worker; pending requests reject with `reason` (or their own, by id). */
  #restart(reason, reasons = {}) {
    this.#worker?.terminate();
    const pending = [...this.#pending.entries()];
    this.#pending.clear();
    this.#spawn();
    for (const [id, p] of pending) p.reject(reasons[id] ?? reason);
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
}
