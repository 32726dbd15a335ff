// The main thread's side of the Draco worker: decode(payload) -> DecodedMesh.
import type { DecodeRequest, DecodeResponse, DecodedMesh } from './decoded_mesh.ts';

export class DracoDecoder {
  private worker: Worker | null = null;
  private nextId = 1;
  private readonly pending = new Map<number, { resolve: (m: DecodedMesh) => void; reject: (e: Error) => void }>();

  private start(): Worker {
    if (this.worker) return this.worker;
    const worker = new Worker(new URL('./draco_worker.ts', import.meta.url), { type: 'module', name: 'draco' });
    worker.onmessage = (ev: MessageEvent<DecodeResponse>) => {
      const r = ev.data;
      const p = this.pending.get(r.id);
      if (!p) return;
      this.pending.delete(r.id);
      if (r.ok) p.resolve(r.mesh);
      else p.reject(new Error(r.error));
    };
    worker.onerror = (ev: ErrorEvent) => {
      const error = new Error(`the Draco worker failed: ${ev.message || 'unknown error'}`);
      for (const p of this.pending.values()) p.reject(error);
      this.pending.clear();
      worker.terminate();
      this.worker = null;
    };
    this.worker = worker;
    return worker;
  }

  /** Decodes a Draco bitstream in the worker. The payload's buffer is transferred. */
  decode(payload: Uint8Array): Promise<DecodedMesh> {
    const worker = this.start();
    const id = this.nextId++;
    // Transfer a buffer that holds exactly the payload.
    const buffer = payload.byteOffset === 0 && payload.byteLength === payload.buffer.byteLength ? (payload.buffer as ArrayBuffer) : payload.slice().buffer;
    return new Promise<DecodedMesh>((resolve, reject) => {
      this.pending.set(id, { resolve, reject });
      const request: DecodeRequest = { id, payload: buffer };
      worker.postMessage(request, [buffer]);
    });
  }

  dispose(): void {
    this.worker?.terminate();
    this.worker = null;
    for (const p of this.pending.values()) p.reject(new Error('decoder disposed'));
    this.pending.clear();
  }
}
