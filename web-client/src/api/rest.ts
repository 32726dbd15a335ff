// The REST half of protocol/API.md: list, upload, get, delete meshes.
import type { ErrorBody, Health, Mesh } from './types.ts';

const BASE = '/api/v1';

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

async function request<T>(path: string, init?: RequestInit): Promise<T> {
  let response: Response;
  try {
    response = await fetch(BASE + path, init);
  } catch (e) {
    throw new ApiError(0, 'network', `cannot reach the server: ${(e as Error).message}`);
  }
  if (!response.ok) throw await failure(response);
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
  return request<void>(`/meshes/${encodeURIComponent(id)}`, { method: 'DELETE' });
}

/** The URL that downloads a mesh converted to `format` (obj, off, ply, stl, glb, drc). */
export function downloadUrl(id: string, format: string): string {
  return `${BASE}/meshes/${encodeURIComponent(id)}/download?format=${encodeURIComponent(format)}`;
}
