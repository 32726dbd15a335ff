// The binary transfers of the WebSocket (protocol/API.md): a payload in
// binary frames between a begin and an end text message (get_mesh's Draco
// stream, get_slice, get_animation), its chunks put together in order and
// checked against what the begin message announced. ws.ts keeps the
// requests; these functions move one transfer along.
import { ChunkAssembler, FrameError, FrameKind, type Frame } from './frames.ts';
import type { MeshBegin } from './types.ts';
import type { Axis } from './voxel_slice.ts';

/** The `slice` text frame that precedes a slice's binary frames (API.md). */
export interface SliceBegin {
  axis: Axis;
  index: number;
  width: number;
  height: number;
  dims: [number, number, number];
  voxel_size: number;
  origin: [number, number, number];
  bytes: number;
  chunks: number;
}

export interface MeshTransfer {
  begin: MeshBegin;
  /** The whole Draco bitstream, chunks joined in order. */
  payload: Uint8Array;
}

export interface GetMeshOptions {
  /** Position quantization bits, 1..30 (the server's default is 14). */
  quantization?: number;
  /** Called as chunks arrive: payload bytes received so far and the total. */
  onProgress?: (received: number, total: number) => void;
  /** Called when the get_mesh request has been sent. */
  onSent?: () => void;
  /** Called when mesh_begin arrives. */
  onBegin?: (begin: MeshBegin) => void;
  /**
   * Asks for a big mesh's preview first (lod "progressive"): called with the
   * decimated preview's transfer, before the full mesh arrives (then onBegin
   * and onProgress start again for it).  Small meshes come in one reply.
   */
  onPreview?: (preview: MeshTransfer) => void;
  /** Aborting forgets the request; chunks still arriving for it are dropped. */
  signal?: AbortSignal;
}

export type Pending =
  | { kind: 'reply'; expect: string; resolve: (msg: Record<string, unknown>) => void; reject: (e: Error) => void }
  | {
      // A payload in binary frames of one kind between a begin and an end
      // text message (get_slice, get_animation), decoded once complete.
      kind: 'payload';
      beginType: string;
      endType: string;
      frameKind: number;
      begin: Record<string, unknown> | null;
      assembler: ChunkAssembler;
      finish: (begin: Record<string, unknown>, payload: Uint8Array) => Promise<void>;
      reject: (e: Error) => void;
    }
  | {
      kind: 'mesh';
      begin: MeshBegin | null;
      assembler: ChunkAssembler;
      options: GetMeshOptions;
      resolve: (t: MeshTransfer) => void;
      reject: (e: Error) => void;
    };

/** A transfer in flight, as `receiveTransferText` sees it: its request id, and how to end it. */
export interface TransferOwner {
  readonly id: number;
  /** Drops the transfer from the requests in flight (it has settled). */
  forget(): void;
  /** Drops it and rejects it with `error`. */
  fail(error: Error): void;
}

/** A text message for a transfer in flight (not an error: the socket fails those itself). */
export function receiveTransferText(p: Exclude<Pending, { kind: 'reply' }>, type: unknown, msg: Record<string, unknown>, owner: TransferOwner): void {
  if (p.kind === 'payload') {
    if (type === p.beginType) {
      p.begin = msg;
    } else if (type === p.endType) {
      owner.forget();
      const begin = p.begin;
      if (!begin) {
        p.reject(new Error(`${p.endType} without ${p.beginType}`));
        return;
      }
      let payload: Uint8Array;
      try {
        payload = p.assembler.result();
      } catch (e) {
        p.reject(e as Error);
        return;
      }
      p.finish(begin, payload).catch((e: Error) => p.reject(e));
    }
    return;
  }
  if (type === 'mesh_begin') {
    const begin = msg as unknown as MeshBegin;
    if (begin.encoding !== 'draco') {
      owner.fail(new Error(`unsupported mesh encoding "${begin.encoding}"`));
      return;
    }
    p.begin = begin;
    p.options.onBegin?.(begin);
    p.options.onProgress?.(p.assembler.bytesReceived, begin.bytes);
  } else if (type === 'mesh_end') {
    const preview = p.begin?.level === 'preview' && p.options.onPreview !== undefined;
    if (!preview) owner.forget();
    try {
      if (!p.begin) throw new Error('mesh_end without mesh_begin');
      let payload: Uint8Array;
      if (p.begin.bytes === 0 && p.assembler.total === null) {
        payload = new Uint8Array(0);
      } else {
        payload = p.assembler.result();
      }
      if (payload.byteLength !== p.begin.bytes) {
        throw new FrameError(`received ${payload.byteLength} bytes, mesh_begin announced ${p.begin.bytes}`);
      }
      if (preview) {
        // The full mesh follows on the same request id.
        const begin = p.begin;
        p.begin = null;
        p.assembler = new ChunkAssembler(owner.id);
        p.options.onPreview!({ begin, payload });
      } else {
        p.resolve({ begin: p.begin, payload });
      }
    } catch (e) {
      if (preview) owner.fail(e as Error);
      else p.reject(e as Error);
    }
  }
}

/** A binary frame for a transfer in flight: added to its chunks; throws when it does not belong there. */
export function receiveTransferFrame(p: Exclude<Pending, { kind: 'reply' }>, frame: Frame): void {
  if (p.kind === 'payload') {
    if (frame.header.kind !== p.frameKind) {
      throw new FrameError(`frame kind ${frame.header.kind}, expected ${p.frameKind} (${p.beginType})`);
    }
    p.assembler.add(frame);
    return;
  }
  if (frame.header.kind !== FrameKind.DracoMesh) {
    throw new FrameError(`frame kind ${frame.header.kind}, expected ${FrameKind.DracoMesh} (Draco mesh)`);
  }
  if (p.begin && frame.header.total !== p.begin.bytes) {
    throw new FrameError(`frame says ${frame.header.total} bytes, mesh_begin said ${p.begin.bytes}`);
  }
  p.assembler.add(frame);
  p.options.onProgress?.(p.assembler.bytesReceived, frame.header.total);
}
