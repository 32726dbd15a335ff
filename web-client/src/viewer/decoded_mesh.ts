// What the Draco worker hands back to the main thread: plain typed arrays,
// transferred (not copied) with postMessage.
import type { WorkerTiming } from './timings.ts';

export interface DecodedColors {
  array: Float32Array | Uint8Array | Uint16Array;
  /** 3 (RGB) or 4 (RGBA). */
  itemSize: number;
  /** True for integer colours meant as 0..1 (Uint8 / Uint16). */
  normalized: boolean;
}

export interface MaterialGroup {
  start: number;
  count: number;
  material: number;
}

export interface DecodedMesh {
  /** xyz per vertex. */
  positions: Float32Array;
  /** Three vertex indices per triangle; empty for a point cloud. */
  indices: Uint32Array;
  /** xyz per vertex, or null when the payload has none. */
  normals: Float32Array | null;
  colors: DecodedColors | null;
  /** uv per vertex (OBJ's convention: v = 0 at the image's bottom), or null when the payload has none. */
  uvs: Float32Array | null;
  /**
   * Runs of faces by material (the server's "material" attribute, for a mesh
   * with several materials), the indices sorted so each material's faces are
   * contiguous: start and count in indices, material an index into the
   * mesh's `materials`. Null for a one-material mesh.
   */
  groups: MaterialGroup[] | null;
  /**
   * Where the faces were sorted by material: the face of the Draco stream
   * each face of `indices` was (its position in the decoder's order). Null:
   * the decoder's order.
   */
  faceSource: Uint32Array | null;
  vertices: number;
  faces: number;
  /** Whether the stream was a Draco point cloud (no faces: drawn as points, viewer/points_renderer.ts). */
  points: boolean;
  /** How long the worker took, measured inside it. */
  timing: WorkerTiming;
}

export interface DecodeRequest {
  id: number;
  payload: ArrayBuffer;
}

export type DecodeResponse = { id: number; ok: true; mesh: DecodedMesh } | { id: number; ok: false; error: string };
