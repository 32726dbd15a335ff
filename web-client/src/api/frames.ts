// The binary WebSocket frame of protocol/API.md ("Binary frame"): a 32-byte
// little-endian header, then one chunk of a payload. Pure code (no DOM, no
// three.js) so that node's test runner checks it against the sample frames in
// tests/data/frames/, the same files the server's tests use.
//
// | offset | type    | field                               |
// |--------|---------|-------------------------------------|
// | 0      | 4 bytes | magic "CGVF"                        |
// | 4      | u16     | version = 1                         |
// | 6      | u16     | kind: 1 = Draco mesh, 2 = voxel slice, 3 = animation |
// | 8      | u32     | request_id                          |
// | 12     | u32     | chunk_index (0-based)               |
// | 16     | u32     | chunk_count                         |
// | 20     | u32     | header_bytes = 32                   |
// | 24     | u64     | total payload bytes (all chunks)    |

export const FRAME_MAGIC = 'CGVF';
export const FRAME_VERSION = 1;
export const FRAME_HEADER_BYTES = 32;
/** Chunk payloads are at most 4 MiB (API.md). */
export const FRAME_MAX_CHUNK_BYTES = 4 * 1024 * 1024;

export const FrameKind = {
  DracoMesh: 1,
  VoxelSlice: 2,
  Animation: 3,
} as const;

/** The header's fields, named as in API.md. */
export interface FrameHeader {
  magic: string;
  version: number;
  kind: number;
  request_id: number;
  chunk_index: number;
  chunk_count: number;
  header_bytes: number;
  /** Total payload bytes of all chunks together. */
  total: number;
}

export interface Frame {
  header: FrameHeader;
  /** This chunk's payload: a view into the frame's buffer, not a copy. */
  payload: Uint8Array;
}

/** A frame that does not follow API.md; the message says which field and why. */
export class FrameError extends Error {
  constructor(message: string) {
    super(message);
    this.name = 'FrameError';
  }
}

function asBytes(data: ArrayBuffer | ArrayBufferView): Uint8Array {
  if (data instanceof Uint8Array) return data;
  if (ArrayBuffer.isView(data)) return new Uint8Array(data.buffer, data.byteOffset, data.byteLength);
  return new Uint8Array(data);
}

/**
 * Reads and checks the 32-byte header at the start of `data`.
 * Throws FrameError when the frame is shorter than its header, the magic is
 * not "CGVF", the version is not 1, header_bytes is under 32 or beyond the
 * frame, chunk_count is 0, chunk_index is not below chunk_count, or the total
 * does not fit in a JavaScript number.
 */
export function decodeFrameHeader(data: ArrayBuffer | ArrayBufferView): FrameHeader {
  const bytes = asBytes(data);
  if (bytes.byteLength < FRAME_HEADER_BYTES) {
    throw new FrameError(`frame of ${bytes.byteLength} bytes is shorter than the ${FRAME_HEADER_BYTES}-byte header`);
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const magic = String.fromCharCode(bytes[0]!, bytes[1]!, bytes[2]!, bytes[3]!);
  if (magic !== FRAME_MAGIC) {
    throw new FrameError(`bad magic ${JSON.stringify(magic)}, expected "${FRAME_MAGIC}"`);
  }
  const version = view.getUint16(4, true);
  if (version !== FRAME_VERSION) {
    throw new FrameError(`unsupported frame version ${version}, expected ${FRAME_VERSION}`);
  }
  const kind = view.getUint16(6, true);
  const request_id = view.getUint32(8, true);
  const chunk_index = view.getUint32(12, true);
  const chunk_count = view.getUint32(16, true);
  const header_bytes = view.getUint32(20, true);
  const total64 = view.getBigUint64(24, true);
  if (header_bytes < FRAME_HEADER_BYTES) {
    throw new FrameError(`header_bytes ${header_bytes} is below ${FRAME_HEADER_BYTES}`);
  }
  if (header_bytes > bytes.byteLength) {
    throw new FrameError(`header_bytes ${header_bytes} is beyond the frame's ${bytes.byteLength} bytes`);
  }
  if (chunk_count === 0) {
    throw new FrameError('chunk_count is 0');
  }
  if (chunk_index >= chunk_count) {
    throw new FrameError(`chunk_index ${chunk_index} is not below chunk_count ${chunk_count}`);
  }
  if (total64 > BigInt(Number.MAX_SAFE_INTEGER)) {
    throw new FrameError(`total ${total64} bytes is too large`);
  }
  return {
    magic,
    version,
    kind,
    request_id,
    chunk_index,
    chunk_count,
    header_bytes,
    total: Number(total64),
  };
}

/** Splits a binary frame into its checked header and its chunk payload. */
export function decodeFrame(data: ArrayBuffer | ArrayBufferView): Frame {
  const bytes = asBytes(data);
  const header = decodeFrameHeader(bytes);
  const payload = bytes.subarray(header.header_bytes);
  if (payload.byteLength > header.total) {
    throw new FrameError(`chunk of ${payload.byteLength} bytes is larger than the total ${header.total}`);
  }
  return { header, payload };
}

/** Writes a frame (header + payload); the inverse of decodeFrame, for tests and tools. */
export function encodeFrame(fields: Pick<FrameHeader, 'kind' | 'request_id' | 'chunk_index' | 'chunk_count' | 'total'>, payload: Uint8Array): Uint8Array {
  const out = new Uint8Array(FRAME_HEADER_BYTES + payload.byteLength);
  const view = new DataView(out.buffer);
  for (let i = 0; i < 4; ++i) out[i] = FRAME_MAGIC.charCodeAt(i);
  view.setUint16(4, FRAME_VERSION, true);
  view.setUint16(6, fields.kind, true);
  view.setUint32(8, fields.request_id, true);
  view.setUint32(12, fields.chunk_index, true);
  view.setUint32(16, fields.chunk_count, true);
  view.setUint32(20, FRAME_HEADER_BYTES, true);
  view.setBigUint64(24, BigInt(fields.total), true);
  out.set(payload, FRAME_HEADER_BYTES);
  return out;
}

/**
 * Collects the chunks of one payload, in any order, and joins them in
 * chunk_index order. Every chunk must carry the same request_id, kind,
 * chunk_count and total; a repeated chunk_index or a byte count that
 * overshoots the total is a FrameError.
 */
export class ChunkAssembler {
  readonly request_id: number;
  private expected: { kind: number; chunk_count: number; total: number } | null = null;
  private readonly chunks = new Map<number, Uint8Array>();
  private received = 0;

  constructor(request_id: number) {
    this.request_id = request_id;
  }

  /** Payload bytes received so far. */
  get bytesReceived(): number {
    return this.received;
  }

  /** Total payload bytes, known once the first chunk has arrived (else null). */
  get total(): number | null {
    return this.expected ? this.expected.total : null;
  }

  get kind(): number | null {
    return this.expected ? this.expected.kind : null;
  }

  get complete(): boolean {
    return this.expected !== null && this.chunks.size === this.expected.chunk_count;
  }

  /** Adds one chunk; returns true when it was the last one missing. */
  add(frame: Frame): boolean {
    const h = frame.header;
    if (h.request_id !== this.request_id) {
      throw new FrameError(`chunk for request ${h.request_id} given to request ${this.request_id}`);
    }
    if (this.expected === null) {
      this.expected = { kind: h.kind, chunk_count: h.chunk_count, total: h.total };
    } else {
      const e = this.expected;
      if (h.kind !== e.kind || h.chunk_count !== e.chunk_count || h.total !== e.total) {
        throw new FrameError(
          `chunk ${h.chunk_index} says kind ${h.kind}, ${h.chunk_count} chunks, ${h.total} bytes; ` +
            `earlier chunks said kind ${e.kind}, ${e.chunk_count} chunks, ${e.total} bytes`,
        );
      }
    }
    if (this.chunks.has(h.chunk_index)) {
      throw new FrameError(`chunk ${h.chunk_index} received twice`);
    }
    if (this.received + frame.payload.byteLength > this.expected.total) {
      throw new FrameError(`chunks add up to more than the total ${this.expected.total} bytes`);
    }
    // Copy: the frame's buffer may be reused by the caller.
    this.chunks.set(h.chunk_index, frame.payload.slice());
    this.received += frame.payload.byteLength;
    return this.complete;
  }

  /** The whole payload, chunks joined in chunk_index order. */
  result(): Uint8Array {
    if (!this.expected || !this.complete) {
      const have = this.chunks.size;
      const want = this.expected ? this.expected.chunk_count : '?';
      throw new FrameError(`payload incomplete: ${have} of ${want} chunks`);
    }
    if (this.received !== this.expected.total) {
      throw new FrameError(`chunks add up to ${this.received} bytes, the header says ${this.expected.total}`);
    }
    const out = new Uint8Array(this.expected.total);
    let offset = 0;
    for (let i = 0; i < this.expected.chunk_count; ++i) {
      const chunk = this.chunks.get(i)!;
      out.set(chunk, offset);
      offset += chunk.byteLength;
    }
    return out;
  }
}
