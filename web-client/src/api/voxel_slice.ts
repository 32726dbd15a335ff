// The voxel-slice payload of protocol/API.md (frame kind 2): a 64-byte
// little-endian header, then the slice's values compressed with zlib, which
// the browser inflates with DecompressionStream('deflate') (RFC 1950).

export const SLICE_HEADER_BYTES = 64;
export const AXES = ['x', 'y', 'z'] as const;
export type Axis = (typeof AXES)[number];

export interface VoxelSlice {
  axis: Axis;
  index: number;
  width: number;
  height: number;
  /** width * height values, row by row (API.md gives which axis runs fastest). */
  values: Uint8Array | Float32Array;
  voxelSize: number;
  /** World position of the lowest corner of the slice's first voxel. */
  corner: [number, number, number];
}

export async function inflate(bytes: Uint8Array): Promise<Uint8Array> {
  const stream = new Blob([bytes as BlobPart]).stream().pipeThrough(new DecompressionStream('deflate'));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

/** Parses and inflates a slice payload; throws on a malformed one. */
export async function decodeSlicePayload(payload: Uint8Array): Promise<VoxelSlice> {
  if (payload.byteLength < SLICE_HEADER_BYTES) throw new Error('voxel slice payload shorter than its header');
  const view = new DataView(payload.buffer, payload.byteOffset, payload.byteLength);
  const magic = String.fromCharCode(payload[0], payload[1], payload[2], payload[3]);
  if (magic !== 'CGVS') throw new Error(`voxel slice magic "${magic}", expected "CGVS"`);
  if (view.getUint16(4, true) !== 1) throw new Error('voxel slice version is not 1');
  const axis = view.getUint8(6);
  const type = view.getUint8(7);
  if (axis > 2 || (type !== 1 && type !== 2)) throw new Error('bad axis or value type in a voxel slice');
  const width = view.getUint32(12, true);
  const height = view.getUint32(16, true);
  const raw = view.getUint32(24, true);
  const packed = view.getUint32(28, true);
  if (view.getUint32(20, true) !== 1 || raw !== width * height * (type === 2 ? 4 : 1) || packed !== payload.byteLength - SLICE_HEADER_BYTES) {
    throw new Error('inconsistent sizes in a voxel slice header');
  }
  const bytes = await inflate(payload.subarray(SLICE_HEADER_BYTES));
  if (bytes.byteLength !== raw) throw new Error(`voxel slice inflated to ${bytes.byteLength} bytes, expected ${raw}`);
  const values = type === 2 ? new Float32Array(bytes.buffer, bytes.byteOffset, width * height) : bytes;
  return {
    axis: AXES[axis],
    index: view.getUint32(8, true),
    width,
    height,
    values,
    voxelSize: view.getFloat64(32, true),
    corner: [view.getFloat64(40, true), view.getFloat64(48, true), view.getFloat64(56, true)],
  };
}
