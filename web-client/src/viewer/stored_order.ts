// The mesh in the server's stored order (vertices and faces as the file has
// them, which fields and selections use), made from the mesh the viewer
// streamed: Draco renumbers both, and the server says where each streamed
// point and face came from (GET /meshes/{id}/stored_order,
// protocol/stored_order.h). No second download of the mesh.
import type { DecodedMesh } from './decoded_mesh.ts';
import type { PlyMesh } from './ply.ts';

/** Each streamed point's stored vertex and each streamed face's stored face, in the decoder's order. */
export interface StoredOrder {
  points: Uint32Array;
  faces: Uint32Array;
}

/** The stored order from its bytes: zlib of 32-bit words P, F, then P and F differences. */
export async function unpackStoredOrder(packed: ArrayBuffer): Promise<StoredOrder> {
  const raw = await new Response(new Blob([packed]).stream().pipeThrough(new DecompressionStream('deflate'))).arrayBuffer();
  const words = new Uint32Array(raw, 0, Math.floor(raw.byteLength / 4));
  const points = words[0] ?? 0;
  const faces = words[1] ?? 0;
  if (raw.byteLength !== 4 * (2 + points + faces)) throw new Error(`the stored order has ${raw.byteLength} bytes, not 8 + 4 × (${points} + ${faces})`);
  const sums = (from: number, n: number) => {
    const out = words.slice(from, from + n);
    let previous = 0;
    for (let i = 0; i < n; ++i) out[i] = previous = (previous + out[i]) >>> 0; // differences modulo 2^32
    return out;
  };
  return { points: sums(2, points), faces: sums(2 + points, faces) };
}

/**
 * The stored mesh from a streamed one: `vertices` stored vertices (the
 * report's count: a vertex no face uses is not streamed and stays at the
 * origin), each at its point's (quantized) position; each face at its stored
 * index with its points' stored vertices, in the stream's turn.
 */
export function storedMesh(decoded: DecodedMesh, order: StoredOrder, vertices: number): PlyMesh {
  const faces = decoded.indices.length / 3;
  if (order.points.length !== decoded.vertices || order.faces.length !== faces) {
    throw new Error(`the stored order is of ${order.points.length} points and ${order.faces.length} faces, the mesh streamed ${decoded.vertices} and ${faces}`);
  }
  const ids = order.points;
  let count = vertices;
  for (let p = 0; p < ids.length; ++p) count = Math.max(count, ids[p] + 1);
  const positions = new Float32Array(3 * count);
  for (let p = 0; p < ids.length; ++p) {
    const v = 3 * ids[p];
    positions[v] = decoded.positions[3 * p];
    positions[v + 1] = decoded.positions[3 * p + 1];
    positions[v + 2] = decoded.positions[3 * p + 2];
  }
  const indices = new Uint32Array(3 * faces);
  const source = decoded.faceSource;
  for (let k = 0; k < faces; ++k) {
    const s = 3 * order.faces[source ? source[k] : k];
    indices[s] = ids[decoded.indices[3 * k]];
    indices[s + 1] = ids[decoded.indices[3 * k + 1]];
    indices[s + 2] = ids[decoded.indices[3 * k + 2]];
  }
  return { positions, indices, vertices: count, faces };
}
