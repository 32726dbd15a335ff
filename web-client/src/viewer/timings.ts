// Timings of one mesh load, from the moment the page sends get_mesh to the
// GPU having drawn the first frame that shows the mesh. Each step is a
// performance mark ("cgview:request", ...) and each phase a performance
// measure ("cgview:wait", ...), so a load shows in DevTools' Performance
// panel; the finished load's durations are also a plain object of
// milliseconds, which the app exposes as window.__cgview.timings
// (bench/browser_bench.mjs reads it).

/** The steps of a load, in order. */
export type LoadStep =
  | 'request' // get_mesh sent
  | 'first-byte' // mesh_begin received: the server has the Draco payload ready
  | 'first-chunk' // the first binary chunk received
  | 'last-chunk' // the last binary chunk received
  | 'decode-start' // chunks joined, payload handed to the Draco worker
  | 'decode-end' // decoded arrays back from the worker
  | 'geometry-built' // three.js geometry and material made
  | 'first-frame' // the first frame with the mesh rendered (renderer.render() returned)
  | 'gpu-done'; // the GPU has finished that frame

/** What the Draco worker measured itself (performance.now() inside the worker). */
export interface WorkerTiming {
  /** Waiting for the WASM decoder to load (0 once it has loaded). */
  initMs: number;
  /** Decoding the payload and copying the arrays out of the WASM heap. */
  decodeMs: number;
}

/** The durations of one finished load, in milliseconds. */
export interface LoadTimings {
  /** request → first-byte: waiting for the server (Draco encode or cache). */
  waitMs: number;
  /** first-byte → last-chunk: receiving all chunks. */
  downloadMs: number;
  /** last-chunk → decode-start: mesh_end, joining the chunks. */
  joinMs: number;
  /** decode-start → decode-end, seen from the page: worker start, decoder load, decode, arrays back. */
  decodeMs: number;
  /** The worker's own decode time (part of decodeMs). */
  workerDecodeMs: number;
  /** The worker's wait for the WASM decoder (part of decodeMs). */
  workerInitMs: number;
  /** decode-end → geometry-built. */
  buildMs: number;
  /** geometry-built → first-frame: the next animation frame, GPU upload, shaders, the first render call. */
  renderMs: number;
  /** first-frame → gpu-done: the GPU executing that frame's commands. */
  gpuMs: number;
  /** request → first-chunk. */
  firstChunkMs: number;
  /** request → first-frame. */
  firstFrameMs: number;
  /** request → gpu-done: wait + download + join + decode + build + render + gpu. */
  totalMs: number;
}

const PREFIX = 'cgview:';

const PHASES: ReadonlyArray<[measure: string, from: LoadStep, to: LoadStep]> = [
  ['wait', 'request', 'first-byte'],
  ['download', 'first-byte', 'last-chunk'],
  ['join', 'last-chunk', 'decode-start'],
  ['decode', 'decode-start', 'decode-end'],
  ['build', 'decode-end', 'geometry-built'],
  ['render', 'geometry-built', 'first-frame'],
  ['gpu', 'first-frame', 'gpu-done'],
  ['total', 'request', 'gpu-done'],
];

const STEPS: readonly LoadStep[] = ['request', 'first-byte', 'first-chunk', 'last-chunk', 'decode-start', 'decode-end', 'geometry-built', 'first-frame', 'gpu-done'];

/** Collects the marks of one load. A step marked twice keeps its first time. */
export class LoadTimer {
  private readonly times = new Map<LoadStep, number>();
  private worker: WorkerTiming = { initMs: 0, decodeMs: 0 };

  mark(step: LoadStep): void {
    if (this.times.has(step)) return;
    if (step === 'request') clearEntries(); // the timeline keeps the latest load only
    this.times.set(step, performance.mark(PREFIX + step).startTime);
  }

  setWorkerTiming(timing: WorkerTiming): void {
    this.worker = timing;
  }

  /**
   * Marks 'gpu-done' once the GPU has executed the commands issued so far
   * (call it right after the first frame): a WebGL2 fence, polled without
   * blocking. Resolves then; at once where there is no fence to be had.
   */
  markGpuDone(gl: WebGLRenderingContext | WebGL2RenderingContext): Promise<void> {
    const sync = gl instanceof WebGL2RenderingContext ? gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0) : null;
    if (!sync || !(gl instanceof WebGL2RenderingContext)) {
      this.mark('gpu-done');
      return Promise.resolve();
    }
    gl.flush();
    return new Promise((resolve) => {
      // A fence's status only changes between tasks, so poll from timeouts.
      const poll = () => {
        if (gl.isContextLost() || gl.getSyncParameter(sync, gl.SYNC_STATUS) === gl.SIGNALED) {
          this.mark('gpu-done');
          gl.deleteSync(sync);
          resolve();
        } else {
          setTimeout(poll, 2);
        }
      };
      setTimeout(poll, 0);
    });
  }

  /** Adds the measures to the timeline and returns the durations. */
  finish(): LoadTimings {
    const at = (step: LoadStep): number => this.times.get(step) ?? NaN;
    // A step that did not happen (an empty payload has no chunks) takes the time of the one before.
    for (let i = 1; i < STEPS.length; ++i) {
      if (!this.times.has(STEPS[i]!) && this.times.has(STEPS[i - 1]!)) this.times.set(STEPS[i]!, at(STEPS[i - 1]!));
    }
    const span = (from: LoadStep, to: LoadStep): number => at(to) - at(from);
    for (const [name, from, to] of PHASES) {
      if (this.times.has(from) && this.times.has(to)) performance.measure(PREFIX + name, { start: at(from), end: at(to) });
    }
    return {
      waitMs: span('request', 'first-byte'),
      downloadMs: span('first-byte', 'last-chunk'),
      joinMs: span('last-chunk', 'decode-start'),
      decodeMs: span('decode-start', 'decode-end'),
      workerDecodeMs: this.worker.decodeMs,
      workerInitMs: this.worker.initMs,
      buildMs: span('decode-end', 'geometry-built'),
      renderMs: span('geometry-built', 'first-frame'),
      gpuMs: span('first-frame', 'gpu-done'),
      firstChunkMs: span('request', 'first-chunk'),
      firstFrameMs: span('request', 'first-frame'),
      totalMs: span('request', 'gpu-done'),
    };
  }
}

function clearEntries(): void {
  for (const e of performance.getEntriesByType('mark')) if (e.name.startsWith(PREFIX)) performance.clearMarks(e.name);
  for (const e of performance.getEntriesByType('measure')) if (e.name.startsWith(PREFIX)) performance.clearMeasures(e.name);
}
