// View links: the view (mesh, camera, display, overlays, field, scene and
// panes) in the page's hash, `#view=...` (viewer/view_state.ts is the
// format). The address bar follows the view: once the view has been still
// for a moment (the camera settled, a mode chosen), the hash is written
// again, so that a reload or a bookmark reopens it and "Copy link" copies
// it. A big change (another mesh, an object added to or taken from the
// scene, a comparison entered or left) makes a new history entry rather
// than rewriting this one, so that Back returns to the view before it; the
// page opened with a link, Back and Forward all show the hash's view.
//
// Beside `view`, the hash may hold what that format has no place for:
// `up=z` (the shown mesh's up axis, which the camera's numbers assume),
// `compare` once per field compared side by side, and `show` once per
// skeleton or vector field drawn or voxel grid whose slices are open
// (`JOB/ARTIFACT`). A live lecture carries the same whole view, read with
// current() and shown with show() (controllers/lecture_broadcast.ts and
// lecture_mirror.ts).
import type { ArtifactRef, SceneEntry } from '../state/app_state.ts';
import { artifactKey, splitKey } from '../state/app_state.ts';
import { applyCamera, readCamera } from '../viewer/camera_state.ts';
import { isIdentity, sanitizeScene, type SceneObjectState } from '../viewer/scene_state.ts';
import { decodeViewHash, encodeViewHash, type FullView, type ViewState } from '../viewer/view_state.ts';
import { describe, jobOf, type AppContext, meshOf } from './context.ts';
import type { Kinds } from '../kinds/registry.ts';
import type { CompareController } from './compare.ts';
import type { MeshLoader } from './mesh_loader.ts';
import type { MeshesController } from './meshes.ts';
import type { SceneController } from './scene.ts';

/** What a view link shows again through: meshes, the scene, the kinds, the comparison. */
export interface LinksDeps {
  meshes: Pick<MeshesController, 'select'>;
  loader: Pick<MeshLoader, 'showing'>;
  scene: Pick<SceneController, 'add' | 'canAdd' | 'change' | 'sideBySide'>;
  kinds: Pick<Kinds, 'field' | 'hide' | 'show' | 'shownKeys'>;
  compare: Pick<CompareController, 'compareFields' | 'leave'>;
}

/** How long the view stays still before the address follows it (a camera's glide ends well within). */
const FOLLOW_MS = 400;

/** What a view's mesh or job missing from the lists may be: the server answers 404 alike for both (a link's reader learns nothing of others' work). */
const NOT_SEEN = 'does not exist or is not shared with you';
const ASK_OWNER = 'ask its owner to share it';

/** Query parameters that look like credentials: never carried into a link. */
const CREDENTIALS = /^(token|access_token|id_token|auth|authorization|api_key|apikey|password|secret)$/i;

/** The view as the hash holds it, and the part whose change makes a new history entry. */
interface WrittenView {
  hash: string;
  entry: string;
}

export class ViewLinks {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: LinksDeps;
  private timer = 0;
  /** Restores under way: the address holds the view being opened, not yet the one shown. */
  private opening = 0;
  /** Counts restores: a later one makes an earlier one stale. */
  private restoring = 0;
  /** The big part of the view the current history entry holds; null: none written yet. */
  private entry: string | null = null;

  constructor(ctx: AppContext, deps: LinksDeps) {
    this.ctx = ctx;
    this.deps = deps;
    window.addEventListener('popstate', () => void this.restore());
  }

  /** The view may have changed (a frame was drawn): the address follows once the view has been still for a moment. */
  changed(): void {
    window.clearTimeout(this.timer);
    this.timer = window.setTimeout(() => this.follow(), FOLLOW_MS);
  }

  /** "Copy link": the view in the page's address, copied to the clipboard where the page may. */
  copy(): void {
    const { store, display, hooks } = this.ctx;
    if (!store.get().selectedId) return this.ctx.error('Choose a mesh first: a view link reopens a mesh.');
    window.clearTimeout(this.timer);
    this.follow();
    const url = location.href;
    display.showLink(url);
    hooks.lastLink = url;
    navigator.clipboard?.writeText(url).then(
      () => this.ctx.notice('View link copied.'),
      () => this.ctx.notice('View link: copy it from the Display panel.'),
    );
  }

  /** Writes the view into the address: a new history entry for a big change, else this entry again. */
  private follow(): void {
    if (this.opening) return;
    const view = this.view();
    if (!view) {
      // The mesh shown is gone (deleted): a reload would only say so. A link that never opened keeps its hash, to be read.
      if (this.entry !== null) history.replaceState(history.state, '', this.url(''));
      this.entry = null;
      return;
    }
    const url = this.url(view.hash);
    if (this.entry !== null && this.entry !== view.entry) history.pushState(null, '', url);
    else if (url !== location.href) history.replaceState(history.state, '', url);
    this.entry = view.entry;
  }

  /** The view shown, as the hash holds it; null with no mesh shown. */
  private view(): WrittenView | null {
    const view = this.current();
    if (!view) return null;
    const { store } = this.ctx;
    const { scene: entries, scenePanes, compared } = store.get();
    // Never the token: it stays in this browser's storage (api/auth.ts).
    const params = new URLSearchParams(encodeViewHash(view.state).slice(1));
    if (view.up === 'z') params.set('up', 'z');
    for (const key of view.compare) params.append('compare', key);
    for (const key of view.show) params.append('show', key);
    const entry = JSON.stringify([view.state.mesh, meshesOf(entries), scenePanes, compared.map((c) => artifactKey(c.jobId, c.artifact))]);
    return { hash: `#${params}`, entry };
  }

  /** The whole view shown (what a link holds, what a lecture's presenter sends); null with no mesh shown. */
  current(): FullView | null {
    const { store, display, viewer } = this.ctx;
    const { deps } = this;
    const { selectedId: meshId, scene: entries, scenePanes, compared } = store.get();
    if (!meshId) return null;
    const { display: settings, overlays } = display.state();
    const state: ViewState = { v: 1, mesh: meshId, camera: readCamera(viewer), display: { ...settings }, overlays: { ...overlays } };
    // The scene, when there is more to it than the mesh as it was loaded (old readers see the mesh alone).
    const scene = entries.map(({ name: _n, object: _o, ...e }) => ({ ...e }));
    if (scene.length > 1 || scene.some((e) => !e.visible || e.color !== null || !isIdentity(e))) state.scene = scene;
    if (scenePanes) state.panes = true;
    const f = deps.kinds.field.drawn();
    if (f && f.meshId === meshId) state.field = { job: f.jobId, artifact: f.artifact, map: f.map, range: f.range };
    // Skeletons side by side are built by their kind from more than a list: only fields come back from a link.
    const compare = compared.every((c) => this.isField(c)) ? compared.map((c) => artifactKey(c.jobId, c.artifact)) : [];
    const show = compared.length ? [] : deps.kinds.shownKeys();
    return { state, up: display.upAxis() === 'z' ? 'z' : 'y', compare, show };
  }

  private isField(c: ArtifactRef): boolean {
    return jobOf(this.ctx, c.jobId)?.artifacts?.some((a) => a.name === c.artifact && a.kind === 'scalar_field') ?? false;
  }

  /** This page's address with `hash`, and without any credential its query may carry. */
  private url(hash: string): string {
    const query = new URLSearchParams(location.search);
    for (const k of [...query.keys()]) if (CREDENTIALS.test(k)) query.delete(k);
    const search = query.toString() ? `?${query}` : '';
    return `${location.origin}${location.pathname}${search}${hash}`;
  }

  /**
   * Opens the view of the page's hash, if it holds one (the page opened with
   * a link, Back, Forward): its mesh, scene, display, overlays, field and
   * comparison, then its camera. Then the address holds the view shown.
   */
  async restore(): Promise<void> {
    let view: FullView | null;
    try {
      view = this.hashView();
    } catch (e) {
      this.ctx.hooks.viewRestored = { error: describe(e) };
      return this.ctx.error(`Cannot open the view link: ${describe(e)}`);
    }
    if (!view) return;
    if (!(await this.show(view, 'view link'))) return;
    const written = this.view();
    if (!written) return;
    history.replaceState(history.state, '', this.url(written.hash));
    this.entry = written.entry;
  }

  /**
   * Shows a whole view (a link's, a lecture's: `source` names it in the
   * messages) as a link is opened. Resolves false when a later one overtook it.
   */
  async show(view: FullView, source: string): Promise<boolean> {
    const token = ++this.restoring;
    ++this.opening;
    try {
      await this.open(view, source, () => token === this.restoring);
    } finally {
      --this.opening;
    }
    return token === this.restoring;
  }

  /** The view of the page's hash; null when it holds none. Throws what is wrong with one that does not check. */
  private hashView(): FullView | null {
    const state = decodeViewHash(location.hash);
    if (!state) return null;
    const params = new URLSearchParams(location.hash.slice(1));
    return { state, up: params.get('up') === 'z' ? 'z' : 'y', compare: params.getAll('compare'), show: params.getAll('show') };
  }

  private async open(view: FullView, source: string, current: () => boolean): Promise<void> {
    const { store, display, viewer, hooks } = this.ctx;
    const { deps } = this;
    const { state } = view;
    let scene: SceneObjectState[] = [];
    try {
      if (state.scene) scene = sanitizeScene(state.scene);
    } catch (e) {
      hooks.viewRestored = { error: describe(e) };
      return this.ctx.error(`Cannot open the ${source}: ${describe(e)}`);
    }
    hooks.viewRestored = null;
    // The server lists what the reader may see: a mesh or job missing from the lists is gone, or another user's not shared with them (the server does not tell which).
    if (!meshOf(this.ctx, state.mesh)) {
      const error = `the mesh ${state.mesh} of the ${source} ${NOT_SEEN}`;
      hooks.viewRestored = { error };
      return this.ctx.error(`Cannot open the ${source}: it shows a mesh (${state.mesh}) that ${NOT_SEEN}: ${ASK_OWNER}.`);
    }
    const field = state.field && jobOf(this.ctx, state.field.job) ? state.field : undefined;
    if (state.field && !field) {
      this.ctx.error(`The ${source} shows a field of a job (${state.field.job}) that ${NOT_SEEN}: ${ASK_OWNER}. The view is shown without it.`);
    }
    const compareKeys = view.compare.filter((k) => jobOf(this.ctx, splitKey(k).jobId));
    const unseenCompared = view.compare.filter((k) => !compareKeys.includes(k));
    if (unseenCompared.length) {
      this.ctx.error(`The ${source} compares fields (${unseenCompared.join(', ')}) that ${NOT_SEEN}: ${ASK_OWNER}. They are left out.`);
    }
    const compare = compareKeys.map(splitKey);
    const shows = view.show.map(splitKey);
    const now = store.get();
    const drawn = deps.kinds.field.drawn();
    // The same mesh and scene with the same field (Back out of a comparison, say): no need to load them again.
    const same =
      now.selectedId === state.mesh &&
      meshesOf(now.scene) === (scene.length ? scene.map((o) => o.mesh) : [state.mesh]).join(' ') &&
      (drawn ? field?.job === drawn.jobId && field.artifact === drawn.artifact : !field);
    if (same) {
      if ((!state.panes && now.scenePanes) || keysOf(compare) !== keysOf(now.compared)) deps.compare.leave();
      display.restore(state.display, state.overlays);
      if (field) {
        deps.kinds.field.chooseMap(field.map);
        deps.kinds.field.setRange(field.range);
      }
    } else {
      deps.meshes.select(state.mesh);
      if (scene[0]) deps.scene.change(0, scene[0]);
      await deps.loader.showing;
      if (!current()) return;
      // A job's output mesh stands in the scene as `job:<job>/<artifact>`: drawn again from its job, missing only when the job is gone.
      const missing = scene.slice(1).filter((o) => !deps.scene.canAdd(o.mesh));
      if (missing.length) {
        this.ctx.error(`The ${source} shows meshes (${missing.map((o) => o.mesh).join(', ')}) that ${NOT_SEEN}: ${ASK_OWNER}. The scene is shown without them.`);
      }
      await Promise.all(
        scene
          .slice(1)
          .filter((o) => !missing.includes(o))
          .map((o) => deps.scene.add(o.mesh, o)),
      );
      if (!current()) return;
      display.restore(state.display, state.overlays);
      if (field) {
        const kind = deps.kinds.field;
        kind.chooseMap(field.map);
        await kind.show(field.job, field.artifact);
        if (!current()) return;
        kind.setRange(field.range);
      }
    }
    display.setUpAxis(view.up);
    // Skeletons and vector fields drawn and a grid's slices, by their kind; those the view does not show go.
    const kindOf = (s: ArtifactRef) => jobOf(this.ctx, s.jobId)?.artifacts?.find((a) => a.name === s.artifact)?.kind;
    if (!compare.length) {
      for (const s of deps.kinds
        .shownKeys()
        .filter((k) => !view.show.includes(k))
        .map(splitKey)) {
        const kind = kindOf(s);
        if (kind) deps.kinds.hide(s.jobId, s.artifact, kind);
      }
    }
    const unknown: string[] = [];
    for (const s of shows) {
      const kind = kindOf(s);
      if (!kind) unknown.push(artifactKey(s.jobId, s.artifact));
      else if (!deps.kinds.shownKeys().includes(artifactKey(s.jobId, s.artifact))) await deps.kinds.show(s.jobId, s.artifact, kind);
      if (!current()) return;
    }
    if (unknown.length) this.ctx.error(`The ${source} shows results (${unknown.join(', ')}) that ${NOT_SEEN}: ${ASK_OWNER}. The view is shown without them.`);
    if (state.panes && !store.get().scenePanes && store.get().scene.length > 1) deps.scene.sideBySide();
    if (compare.length && keysOf(compare) !== keysOf(store.get().compared)) {
      await deps.compare.compareFields(compare);
      if (!current()) return;
    }
    applyCamera(viewer, state.camera);
    const mode = display.state().display.mode;
    viewer.redraw(() => (hooks.viewRestored = { camera: readCamera(viewer), mode }));
  }
}

function meshesOf(entries: readonly SceneEntry[]): string {
  return entries.map((e) => e.mesh).join(' ');
}

function keysOf(list: readonly ArtifactRef[]): string {
  return list.map((c) => artifactKey(c.jobId, c.artifact)).join(' ');
}
