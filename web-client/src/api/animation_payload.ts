// The animation payload of the WebSocket (get_animation, frames of kind 3;
// protocol/animation_frames.h): the .frames bytes with every frame after the
// first replaced by its uint16 difference from the one before, compressed
// with zlib. Decoding inflates and adds the differences back, giving the
// .frames bytes exactly (viewer/frames.ts parses them).
import { inflate } from './voxel_slice.ts';

export async function decodeAnimationPayload(payload: Uint8Array, rawBytes: number): Promise<ArrayBuffer> {
  const raw = await inflate(payload);
  if (raw.byteLength !== rawBytes) throw new Error(`animation inflated to ${raw.byteLength} bytes, expected ${rawBytes}`);
  const view = new DataView(raw.buffer, raw.byteOffset, raw.byteLength);
  if (raw.byteLength < 44 || String.fromCharCode(raw[0]!, raw[1]!, raw[2]!, raw[3]!) !== 'CGVF') throw new Error('not a .frames payload');
  const n = view.getUint32(8, true);
  const f = view.getUint32(12, true);
  const m = view.getUint32(16, true);
  const start = 44 + 12 * f;
  const per = 3 * n;
  if (start + 2 * per * m !== raw.byteLength) throw new Error('the .frames sizes do not add up to its length');
  for (let k = 1; k < m; ++k) {
    const cur = start + 2 * per * k;
    const prev = cur - 2 * per;
    for (let i = 0; i < per; ++i) {
      view.setUint16(cur + 2 * i, (view.getUint16(cur + 2 * i, true) + view.getUint16(prev + 2 * i, true)) & 0xffff, true);
    }
  }
  return raw.buffer.slice(raw.byteOffset, raw.byteOffset + raw.byteLength) as ArrayBuffer;
}
