// What the controllers and the artifact kinds share: the state, the test
// hooks, the viewer and the connection, the display, the panels several of
// them draw in, and the account. What each uses of the other controllers it
// is given explicitly, as its constructor's second argument, typed by what
// it calls (MeshesDeps, SceneDeps, KindDeps...): those made before it as they
// are, and what it asks of one made after it (the scene, the mesh list and
// the kinds ask the comparison and the jobs) as callbacks that app.ts joins.
import { ApiError } from '../api/rest.ts';
import type { Job, Mesh } from '../api/types.ts';
import { ServerError, type CgviewSocket } from '../api/ws.ts';
import type { ProgressPanel } from '../panels/progress.ts';
import type { AppStore } from '../state/app_state.ts';
import type { TestHooks } from '../test_hooks.ts';
import type { MeshTextures } from '../viewer/textures.ts';
import type { Viewer } from '../viewer/viewer.ts';
import type { SelectionTool } from '../viewer/selection_tool.ts';
import type { AccountController } from './account.ts';
import type { DisplayController } from './display.ts';
import type { UndoOffers } from './undo.ts';

export interface AppContext {
  readonly store: AppStore;
  readonly hooks: TestHooks;
  readonly viewer: Viewer;
  readonly socket: CgviewSocket;
  readonly display: DisplayController;
  readonly progress: ProgressPanel;
  readonly textures: MeshTextures;
  readonly selectionTool: SelectionTool;
  /** Offers "Undo" for what destroys (a delete, a cleared selection, a comparison left). */
  readonly undo: UndoOffers;
  /** The signed-in user: who may change what, whose it is. */
  readonly account: AccountController;
  /** Shows an error in the page (and in the hooks' lastError); one of `topic` replaces the last one of it. */
  error(text: string, topic?: string): void;
  /** Takes the messages of `topic` away (what they said no longer holds: a rerun succeeded). */
  dismiss(topic: string): void;
  /** Shows a notice that fades. */
  notice(text: string): void;
  /** Shows a warning: it fades too, but stays longer than a notice. */
  warning(text: string): void;
}

/** An error's words for the page: the server's detail where it gave one. */
export function describe(e: unknown): string {
  if (e instanceof ApiError || e instanceof ServerError) return e.detail || e.message;
  if (e instanceof Error) return e.message;
  return String(e);
}

/** Whether the server refused the request for want of a sign-in (401): the sign-in box asks then, and the error need not be shown. */
export function isUnauthorized(e: unknown): boolean {
  return e instanceof ApiError && e.status === 401;
}

export function isAbort(e: unknown): boolean {
  return e instanceof DOMException && e.name === 'AbortError';
}

/** A mesh by id, as the page knows it (null: not listed). */
export function meshOf(ctx: AppContext, id: string): Mesh | null {
  return ctx.store.get().meshes.find((m) => m.id === id) ?? null;
}

/** A job by id, as the page knows it. */
export function jobOf(ctx: AppContext, id: string): Job | undefined {
  return ctx.store.get().jobs.get(id);
}
