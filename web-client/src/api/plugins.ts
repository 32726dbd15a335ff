// Users' plugins (API.md "Plugins"): one C++ algorithm file each, saved,
// built by the server in a build job and run as any algorithm (a job naming
// the plugin). Listed without their source; read one for its text.
import { request } from './rest.ts';
import type { Job } from './types.ts';

/** One message of the compiler, at its place in the file. */
export interface PluginDiagnostic {
  file: string;
  line: number;
  column: number;
  severity: 'error' | 'warning' | 'note' | 'fatal error' | string;
  message: string;
}

/** "changed": built before, its source saved since and not rebuilt. */
export type PluginBuildState = 'none' | 'building' | 'ok' | 'failed' | 'changed';

export interface PluginBuild {
  state: PluginBuildState;
  /** The last build job, or null. */
  job: string | null;
  error: string | null;
  diagnostics: PluginDiagnostic[];
  /** The names of the algorithms the built library registers. */
  algorithms: string[];
}

export interface Plugin {
  id: string;
  name: string;
  owner: string;
  /** "lab": from the admin's plugin directory, read-only. */
  origin: 'user' | 'lab' | string;
  created: string;
  updated: string;
  source_bytes: number;
  build: PluginBuild;
  /** Present when one plugin is asked for (GET, POST, PUT). */
  source?: string;
}

const path = (id: string, rest = ''): string => `/plugins/${encodeURIComponent(id)}${rest}`;

function json(method: string, body: unknown): RequestInit {
  return { method, headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) };
}

/** The caller's plugins, those shared with them and the lab's, without their source. */
export async function listPlugins(): Promise<Plugin[]> {
  return (await request<{ plugins: Plugin[] }>('/plugins')).plugins;
}

/** One plugin with its source. */
export function getPlugin(id: string): Promise<Plugin> {
  return request<Plugin>(path(id));
}

/** A new plugin (name: 1-64 of A-Z a-z 0-9 _ -), not built yet. */
export function createPlugin(name: string, source: string): Promise<Plugin> {
  return request<Plugin>('/plugins', json('POST', { name, source }));
}

/** Saves a new source and/or renames; a build state "ok" becomes "changed" when the source changed. */
export function updatePlugin(id: string, change: { name?: string; source?: string }): Promise<Plugin> {
  return request<Plugin>(path(id), json('PUT', change));
}

export function deletePlugin(id: string): Promise<void> {
  return request<void>(path(id), { method: 'DELETE' });
}

/**
 * Starts a build: answers the build job (algorithm "plugin_build"), followed
 * as any job. Its end says nothing of the file: read the plugin then.
 */
export function buildPlugin(id: string): Promise<Job> {
  return request<Job>(path(id, '/build'), { method: 'POST' });
}
