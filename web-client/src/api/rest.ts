// The REST half of protocol/API.md: list, upload, get, delete meshes; list
// algorithms; submit, list, get and cancel jobs; fetch their artifacts;
// upload data other tools made; the caller's usage and limits; share and
// unshare meshes and jobs.
import { authFetch } from './auth.ts';
import type { Algorithm, ErrorBody, Health, Job, JobInput, Me, Mesh, Sharing } from './types.ts';

const BASE = '/api/v1';

/** The URL of a server-side render of a mesh (GET /meshes/{id}/render.png), e.g. a thumbnail. */
export function renderUrl(id: string, params: { width?: number; height?: number; mode?: string; azimuth?: number; elevation?: number; field?: string } = {}): string {
  const query = new URLSearchParams();
  for (const [key, value] of Object.entries(params)) {
    if (value !== undefined) query.set(key, String(value));
  }
  const q = query.toString();
  return `${BASE}/meshes/${encodeURIComponent(id)}/render.png${q ? `?${q}` : ''}`;
}

/** A failed request: the HTTP status and the server's error code and detail. */
export class ApiError extends Error {
  readonly status: number;
  readonly code: string;
  readonly detail: string;

  constructor(status: number, code: string, detail: string) {
    super(detail ? `${detail} (${code}, HTTP ${status})` : `${code} (HTTP ${status})`);
    this.name = 'ApiError';
    this.status = status;
    this.code = code;
    this.detail = detail;
  }
}

async function failure(response: Response): Promise<ApiError> {
  const text = await response.text().catch(() => '');
  try {
    const body = JSON.parse(text) as Partial<ErrorBody>;
    if (typeof body.error === 'string') {
      return new ApiError(response.status, body.error, typeof body.detail === 'string' ? body.detail : '');
    }
  } catch {
    // Not JSON (a proxy's error page, say): keep the text.
  }
  return new ApiError(response.status, response.statusText || 'error', text.slice(0, 300));
}

/** A request to the API (BASE + path) with the caller's token: its answer, ok; rejects with an ApiError. */
export async function requestOk(path: string, init?: RequestInit): Promise<Response> {
  let response: Response;
  try {
    response = await authFetch(BASE + path, init);
  } catch (e) {
    throw new ApiError(0, 'network', `cannot reach the server: ${(e as Error).message}`);
  }
  if (!response.ok) throw await failure(response);
  return response;
}

/** A JSON request to the API (BASE + path) with the caller's token; rejects with an ApiError. */
export async function request<T>(path: string, init?: RequestInit): Promise<T> {
  const response = await requestOk(path, init);
  if (response.status === 204) return undefined as T;
  return (await response.json()) as T;
}

export function health(): Promise<Health> {
  return request<Health>('/health');
}

/** Every stored mesh, newest last. */
export async function listMeshes(): Promise<Mesh[]> {
  const body = await request<{ meshes: Mesh[] }>('/meshes');
  return body.meshes;
}

export function getMesh(id: string): Promise<Mesh> {
  return request<Mesh>(`/meshes/${encodeURIComponent(id)}`);
}

/**
 * Uploads a mesh file as the raw request body. The server takes the format
 * from `format` when given, else from the extension of `name`.
 */
export function uploadMesh(name: string, body: Blob | ArrayBuffer, format?: string): Promise<Mesh> {
  const query = new URLSearchParams({ name });
  if (format) query.set('format', format);
  return request<Mesh>(`/meshes?${query}`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/octet-stream' },
    body,
  });
}

export function deleteMesh(id: string): Promise<void> {
  // keepalive: a delete held back for "Undo" is sent as the page goes away, and must outlive it.
  return request<void>(`/meshes/${encodeURIComponent(id)}`, { method: 'DELETE', keepalive: true });
}

/** A mesh file format of the server (API.md, GET /api/v1/formats). */
export interface MeshFormatInfo {
  name: string;
  /** Lowercase, with the dot: ".ply". */
  extensions: string[];
  mime: string;
  can_write: boolean;
  help: string;
}

let formatsAsked: Promise<MeshFormatInfo[]> | null = null;

/** The mesh formats the server reads and writes, asked once (again after a failure). */
export function meshFormats(): Promise<MeshFormatInfo[]> {
  formatsAsked ??= request<{ formats: MeshFormatInfo[] }>('/formats').then(
    (body) => body.formats,
    (e: unknown) => {
      formatsAsked = null;
      throw e;
    },
  );
  return formatsAsked;
}

/** The URL that downloads a mesh converted to `format` (a format of meshFormats() with can_write). */
export function downloadUrl(id: string, format: string): string {
  return `${BASE}/meshes/${encodeURIComponent(id)}/download?format=${encodeURIComponent(format)}`;
}

// Algorithms and jobs (API.md "Algorithms and jobs").

/** Every registered algorithm, each with its params JSON Schema. */
export async function listAlgorithms(): Promise<Algorithm[]> {
  const body = await request<{ algorithms: Algorithm[] }>('/algorithms');
  return body.algorithms;
}

/**
 * Submits a job: 201 with the Job (already `done`, `cached: true`, when the
 * result is stored). `plugin`: the id of the user's plugin the algorithm
 * comes from (its names are the user's own, so the server needs it).
 */
export function submitJob(algorithm: string, inputs: Record<string, JobInput>, params: Record<string, unknown>, plugin?: string): Promise<Job> {
  return request<Job>('/jobs', {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(plugin ? { algorithm, plugin, inputs, params } : { algorithm, inputs, params }),
  });
}

export async function listJobs(): Promise<Job[]> {
  const body = await request<{ jobs: Job[] }>('/jobs');
  return body.jobs;
}

export function getJob(id: string): Promise<Job> {
  return request<Job>(`/jobs/${encodeURIComponent(id)}`);
}

/** Cancels a queued or running job; answers the Job, state `cancelled`. */
export function cancelJob(id: string): Promise<Job> {
  return request<Job>(`/jobs/${encodeURIComponent(id)}/cancel`, { method: 'POST' });
}

/** Deletes an ended job and its results (the server answers 204; a queued or running one it cancels). */
export function deleteJob(id: string): Promise<void> {
  return request<void>(`/jobs/${encodeURIComponent(id)}`, { method: 'DELETE' });
}

/**
 * Uploads a file another tool made (a voxel grid, a skeleton, a scalar field)
 * as the raw request body (POST /data): it comes back as a done `import` Job
 * whose artifact it is. `kind` defaults from the name's extension; `mesh` is
 * the stored mesh it belongs to.
 */
export function uploadData(name: string, body: Blob | ArrayBuffer, options: { kind?: string; mesh?: string } = {}): Promise<Job> {
  const query = new URLSearchParams({ name });
  if (options.kind) query.set('kind', options.kind);
  if (options.mesh) query.set('mesh', options.mesh);
  return request<Job>(`/data?${query}`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/octet-stream' },
    body,
  });
}

/** The URL of a job's artifact in `format` (txt, csv, ply, json, f32 for scalar fields; mesh formats; json for metrics). */
export function artifactUrl(jobId: string, name: string, format: string): string {
  return `${BASE}/jobs/${encodeURIComponent(jobId)}/artifacts/${encodeURIComponent(name)}?format=${encodeURIComponent(format)}`;
}

async function fetchOk(url: string, signal?: AbortSignal): Promise<Response> {
  let response: Response;
  try {
    response = await authFetch(url, { signal });
  } catch (e) {
    if (e instanceof DOMException && e.name === 'AbortError') throw e;
    throw new ApiError(0, 'network', `cannot reach the server: ${(e as Error).message}`);
  }
  if (!response.ok) throw await failure(response);
  return response;
}

/** A scalar field artifact as raw little-endian float32 values (`format=f32`). */
export async function fetchArtifactF32(jobId: string, name: string, signal?: AbortSignal): Promise<Float32Array> {
  const response = await fetchOk(artifactUrl(jobId, name, 'f32'), signal);
  const buffer = await response.arrayBuffer();
  if (buffer.byteLength % 4 !== 0) throw new ApiError(200, 'bad_artifact', `f32 artifact of ${buffer.byteLength} bytes`);
  const view = new DataView(buffer);
  const out = new Float32Array(buffer.byteLength / 4);
  for (let i = 0; i < out.length; ++i) out[i] = view.getFloat32(i * 4, true);
  return out;
}

/** An artifact as JSON (`format=json`): scalar fields, metrics. */
export async function fetchArtifactJson<T = unknown>(jobId: string, name: string, signal?: AbortSignal): Promise<T> {
  const response = await fetchOk(artifactUrl(jobId, name, 'json'), signal);
  return (await response.json()) as T;
}

/** An artifact's bytes in `format` (a mesh artifact as ply, say). */
export async function fetchArtifactBytes(jobId: string, name: string, format: string, signal?: AbortSignal): Promise<ArrayBuffer> {
  const response = await fetchOk(artifactUrl(jobId, name, format), signal);
  return response.arrayBuffer();
}

/** A mesh downloaded in `format` as bytes (the scalar-field renderer reads binary PLY: the server's vertex order). */
export async function fetchMeshBytes(id: string, format: string, signal?: AbortSignal): Promise<ArrayBuffer> {
  const response = await fetchOk(downloadUrl(id, format), signal);
  return response.arrayBuffer();
}

/** Where each point and face of a mesh's Draco stream at `bits` came from (GET /meshes/{id}/stored_order): packed, see viewer/stored_order.ts. */
export async function fetchStoredOrder(id: string, bits = 14, signal?: AbortSignal): Promise<ArrayBuffer> {
  const response = await fetchOk(`${BASE}/meshes/${encodeURIComponent(id)}/stored_order?quantization=${bits}`, signal);
  return response.arrayBuffer();
}

/** A mesh's texture image n (GET /meshes/{id}/textures/{n}), typed by the server (image/png or image/jpeg). */
export async function fetchMeshTexture(id: string, n: number, signal?: AbortSignal): Promise<Blob> {
  const response = await fetchOk(`${BASE}/meshes/${encodeURIComponent(id)}/textures/${n}`, signal);
  return response.blob();
}

/** The caller: user name, storage and jobs used, and their limits (GET /me). */
export function getMe(): Promise<Me> {
  return request<Me>('/me');
}

/** Shares a mesh, a job or a plugin with users and/or everyone, or takes that back (add false). */
export function setSharing(kind: 'meshes' | 'jobs' | 'plugins', id: string, who: { users?: string[]; everyone?: boolean; courses?: string[] }, add: boolean): Promise<Sharing> {
  return request<Sharing>(`/${kind}/${encodeURIComponent(id)}/${add ? 'share' : 'unshare'}`, {
    method: 'POST',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(who),
  });
}
