// The mesh in the server's stored order (vertices and faces as the file has
// them, which fields and selections use), made from the mesh the viewer
// streamed: Draco renumbers both, so the stream carries each point's stored
// vertex (DecodedMesh.vertexIds) and the server sends each streamed face's
// stored index (GET /meshes/{id}/face_order, protocol/face_order.h). No
// second download of the mesh.
import type { DecodedMesh } from './decoded_mesh.ts';
import type { PlyMesh } from './ply.ts';

/** The stored index of each face in the decoder's order, from face_order's bytes (zlib of int32 differences). */
export async function unpackFaceOrder(packed: ArrayBuffer, faces: number): Promise<Uint32Array> {
  const raw = await new Response(new Blob([packed]).stream().pipeThrough(new DecompressionStream('deflate'))).arrayBuffer();
  if (raw.byteLength !== faces * 4) throw new Error(`the face order has ${raw.byteLength / 4} faces, the mesh ${faces}`);
  const order = new Uint32Array(raw);
  let previous = 0;
  for (let f = 0; f < faces; ++f) {
    previous = (previous + order[f]) >>> 0; // differences modulo 2^32
    order[f] = previous;
  }
  return order;
}

/**
 * The stored mesh from a streamed one: `vertices` stored vertices (the
 * report's count: a vertex no face uses is not streamed and stays at the
 * origin), each at its point's (quantized) position; each face at its stored
 * index with its points' stored vertices, in the stream's turn.
 */
export function storedOrder(decoded: DecodedMesh, order: Uint32Array, vertices: number): PlyMesh {
  const ids = decoded.vertexIds;
  if (!ids) throw new Error('the streamed mesh carries no vertex ids');
  const faces = decoded.indices.length / 3;
  if (order.length !== faces) throw new Error(`the face order has ${order.length} faces, the mesh ${faces}`);
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
    const s = 3 * order[source ? source[k] : k];
    indices[s] = ids[decoded.indices[3 * k]];
    indices[s + 1] = ids[decoded.indices[3 * k + 1]];
    indices[s + 2] = ids[decoded.indices[3 * k + 2]];
  }
  return { positions, indices, vertices: count, faces };
}
