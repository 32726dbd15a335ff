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
  /** Whether the mesh has texture coordinates. */
  has_uvs?: boolean;
  /** Its texture images, fetched from /meshes/{id}/textures/{n}; the one on the most faces first. */
  textures?: MeshTexture[];
  /** An OBJ's materials in the order of the material ids of its Draco stream (its groups). */
  materials?: MeshMaterial[];
  /** The diffuse colour (0..1) of its material, when an MTL gave one. */
  kd?: [number, number, number];
  /** The user who uploaded it ("system" for the samples). */
  owner?: string;
  /** A point cloud: no faces, streamed as a Draco point cloud and drawn as points. */
  points?: boolean;
}

export interface MeshMaterial {
  name: string;
  faces: number;
  kd: [number, number, number] | null;
  /** An index into the mesh's textures, or null. */
  texture: number | null;
}

export interface MeshTexture {
  name: string;
  mime: string;
  bytes: number;
  material?: string;
  kd?: [number, number, number];
}

/** GET /api/v1/me: the caller, what they use and their limits (null: none). */
export interface Me {
  user: string;
  admin: boolean;
  /** May create courses (the role teacher, or an admin). */
  teacher: boolean;
  storage_bytes_used: number;
  storage_bytes_limit: number | null;
  jobs_active: number;
  jobs_limit: number | null;
}

/** What POST /meshes|jobs/{id}/share and /unshare answer: who reads the item now. */
export interface Sharing {
  id: string;
  owner: string;
  users: string[];
  everyone: boolean;
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
  /** "preview" (a decimated big mesh, followed by the full one) or "full"; absent from older servers. */
  level?: 'preview' | 'full';
  bytes: number;
  chunks: number;
  vertices: number;
  faces: number;
  has_normals: boolean;
  has_colors: boolean;
}

/** One parameter of an algorithm: a JSON Schema property (API.md "Algorithms and jobs"). */
export interface ParamSchema {
  type: 'integer' | 'number' | 'boolean' | 'string' | string;
  title?: string;
  description?: string;
  default?: unknown;
  minimum?: number;
  maximum?: number;
  enum?: unknown[];
  /** Forms fold it under "Advanced" (render contexts, internal limits). */
  'x-cgview-advanced'?: boolean;
  /** It applies only while the parameter named has one of these values (a boolean's as "true" / "false"). */
  'x-cgview-when'?: { param: string; in: string[] };
  [key: string]: unknown;
}

/** `params` of an Algorithm: a JSON Schema object. */
export interface ParamsSchema {
  type?: 'object';
  properties?: Record<string, ParamSchema>;
  required?: string[];
  additionalProperties?: boolean;
  /** The parameters' names in their declared order, the most used first (`properties` comes sorted by name). */
  'x-cgview-order'?: string[];
  [key: string]: unknown;
}

export interface Algorithm {
  name: string;
  title: string;
  description: string;
  area: string;
  inputs: Array<{ name: string; kind: string; description?: string }>;
  outputs: Array<{ name: string; kind: string }>;
  params: ParamsSchema;
  /** The id of the caller's plugin it comes from (absent: built in); a job of it names the plugin. */
  plugin?: string;
}

export type JobState = 'queued' | 'running' | 'done' | 'failed' | 'cancelled' | 'interrupted';

/** A job's artifact as the Job lists it; `location` and `range` for scalar fields, `count` where it applies. */
export interface ArtifactInfo {
  name: string;
  kind: 'scalar_field' | 'vector_field' | 'mesh' | 'metrics' | string;
  location?: 'vertex' | 'face';
  range?: [number, number];
  count?: number;
  hint?: string;
  /** A vector field's longest finite vector (its arrows are drawn scaled by it). */
  max_length?: number;
  /** The formats GET /jobs/{id}/artifacts/{name}?format=F serves it in (its kind's codec); absent from older servers. */
  formats?: string[];
  /** Its stored size; absent from older servers. */
  bytes?: number;
}

/** A job's input: a stored mesh's id, or an earlier job's output mesh. */
/** A stored mesh's id, or an earlier job's artifact; `name` names the mesh the server stores from an output mesh. */
export type JobInput = string | { job: string; artifact: string; name?: string };

export interface Job {
  id: string;
  owner?: string;
  algorithm: string;
  /** Each input: a mesh id, or an earlier job's artifact (a voxel grid). */
  inputs: Record<string, JobInput>;
  params: Record<string, unknown>;
  state: JobState;
  progress: number;
  stage: string;
  error: string | null;
  cached: boolean;
  created: string | null;
  started: string | null;
  finished: string | null;
  /** How long its run took, its worker's start to its end, in seconds; absent when not known. */
  run_s?: number;
  artifacts: ArtifactInfo[];
  /** What the algorithm (or an import) says the user must know: faces left without a value, parts of a file not used, values missing; absent from older servers. */
  warnings?: string[];
}

/** What a job_progress event carries. */
export type JobProgress = Pick<Job, 'id' | 'state' | 'progress' | 'stage'>;

/** A scalar field artifact fetched as `format=json`. */
export interface ScalarFieldJson {
  name: string;
  location: 'vertex' | 'face';
  hint?: string;
  range: [number, number];
  values: number[];
}

/** Server-to-client events (no request_id). */
export type ServerEvent =
  | { type: 'mesh_added'; mesh: Mesh }
  | { type: 'mesh_deleted'; mesh_id: string }
  | { type: 'job_progress'; job: JobProgress }
  | { type: 'job_done'; job: Job }
  | { type: 'job_failed'; job: Job }
  | { type: 'job_cancelled'; job: Job };

export const SERVER_EVENT_TYPES: ReadonlySet<string> = new Set(['mesh_added', 'mesh_deleted', 'job_progress', 'job_done', 'job_failed', 'job_cancelled']);

/**
 * Whether an algorithm's input of kind `input` takes an object of kind
 * `object`: its own kind, and for points a mesh too (its vertices: a stored
 * mesh, an uploaded cloud among them, is a cloud; protocol/API.md).
 */
export function takesKind(input: string, object: string): boolean {
  return input === object || (input === 'points' && object === 'mesh');
}

/**
 * The id of the stored mesh a job ran on (its input "mesh", or "points"
 * given a stored mesh: what it made is drawn over that one), or null (a job
 * on a voxel grid, on an earlier job's output).
 */
export function jobMeshId(job: Job | undefined): string | null {
  const m = job?.inputs?.mesh ?? job?.inputs?.points;
  return typeof m === 'string' ? m : null;
}
