// JSON shapes of protocol/API.md, as the client reads them.

/** A mesh report: the keys API.md names, plus whatever else the server adds. */
export interface MeshReport {
  vertices: number;
  faces: number;
  edges?: number;
  bbox?: { min: [number, number, number]; max: [number, number, number] };
  components?: number;
  boundary_loops?: number;
  genus?: number;
  manifold?: boolean;
  degenerate_faces?: number;
  [key: string]: unknown;
}

export interface Mesh {
  id: string;
  name: string;
  format: string;
  bytes: number;
  created: string;
  sha256?: string;
  report: MeshReport;
  warnings?: string[];
}

export interface Health {
  status: string;
  version: string;
  meshes: number;
  uptime_s: number;
}

/** The `{"error": code, "detail": sentence}` body of every REST error. */
export interface ErrorBody {
  error: string;
  detail: string;
}

/** The first text frame of a get_mesh answer. */
export interface MeshBegin {
  type: 'mesh_begin';
  request_id: number;
  mesh_id: string;
  encoding: string;
  bytes: number;
  chunks: number;
  vertices: number;
  faces: number;
  has_normals: boolean;
  has_colors: boolean;
}

/** Server-to-client events (no request_id). */
export type ServerEvent =
  | { type: 'mesh_added'; mesh: Mesh }
  | { type: 'mesh_deleted'; mesh_id: string };
