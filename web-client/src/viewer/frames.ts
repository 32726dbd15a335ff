// The .frames format of an animation artifact (chaos_animate; layout in
// protocol/API.md and algorithms/core/animation.h): faces, then every frame's
// positions as uint16 quantized against one box. Decoded once; a frame is
// expanded into a Float32Array position buffer on demand.
export interface PositionFrames {
  vertices: number;
  faces: number;
  frames: number;
  lo: [number, number, number];
  hi: [number, number, number];
  indices: Uint32Array;
  /** 3 * vertices uint16 per frame, frames after each other. */
  quantized: Uint16Array;
}

export function decodeFrames(buffer: ArrayBuffer): PositionFrames {
  const view = new DataView(buffer);
  const fail = (why: string): never => {
    throw new Error(`not a .frames animation: ${why}`);
  };
  if (buffer.byteLength < 44) fail('shorter than its 44-byte header');
  const magic = String.fromCharCode(...new Uint8Array(buffer, 0, 4));
  if (magic !== 'CGVF') fail(`magic ${JSON.stringify(magic)}`);
  if (view.getUint32(4, true) !== 1) fail(`version ${view.getUint32(4, true)}`);
  const vertices = view.getUint32(8, true);
  const faces = view.getUint32(12, true);
  const frames = view.getUint32(16, true);
  const lo: [number, number, number] = [view.getFloat32(20, true), view.getFloat32(24, true), view.getFloat32(28, true)];
  const hi: [number, number, number] = [view.getFloat32(32, true), view.getFloat32(36, true), view.getFloat32(40, true)];
  const need = 44 + 12 * faces + 6 * vertices * frames;
  if (buffer.byteLength !== need) fail(`${buffer.byteLength} bytes where the header needs ${need}`);
  if (frames < 1) fail('no frame');
  // Copies: the offsets need not be aligned for a typed-array view.
  const indices = new Uint32Array(buffer.slice(44, 44 + 12 * faces));
  const quantized = new Uint16Array(buffer.slice(44 + 12 * faces));
  return { vertices, faces, frames, lo, hi, indices, quantized };
}

/** Writes frame k's positions into out (3 * vertices floats). */
export function framePositions(f: PositionFrames, k: number, out: Float32Array): Float32Array {
  const n3 = 3 * f.vertices;
  const base = k * n3;
  const scale = [0, 1, 2].map((a) => (f.hi[a]! - f.lo[a]!) / 65535);
  for (let i = 0; i < n3; i += 3) {
    out[i] = f.lo[0] + scale[0]! * f.quantized[base + i]!;
    out[i + 1] = f.lo[1] + scale[1]! * f.quantized[base + i + 1]!;
    out[i + 2] = f.lo[2] + scale[2]! * f.quantized[base + i + 2]!;
  }
  return out;
}
