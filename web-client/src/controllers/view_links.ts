// View links: the view (mesh, camera, display, overlays, field, scene and
// panes) in the page's #view= hash, made with "Copy link" and opened when the
// page starts with one (viewer/view_state.ts is the format).
import { applyCamera, readCamera } from '../viewer/camera_state.ts';
import { isIdentity, sanitizeScene, type SceneObjectState } from '../viewer/scene_state.ts';
import { decodeViewHash, encodeViewHash, type ViewState } from '../viewer/view_state.ts';
import { describe, type AppContext } from './context.ts';

export class ViewLinks {
  private readonly ctx: AppContext;

  constructor(ctx: AppContext) {
    this.ctx = ctx;
  }

  /** "Copy link": the view in the page's hash; copied to the clipboard where the page may. */
  copy(): void {
    const { store, display, viewer, hooks, app } = this.ctx;
    const { selectedId: meshId, scene: entries, scenePanes } = store.get();
    if (!meshId) return this.ctx.error('Choose a mesh first: a view link reopens a mesh.');
    const { display: settings, overlays } = display.state();
    const state: ViewState = { v: 1, mesh: meshId, camera: readCamera(viewer), display: { ...settings }, overlays: { ...overlays } };
    // The scene, when there is more to it than the mesh as it was loaded (old readers see the mesh alone).
    const scene = entries.map(({ name: _n, object: _o, ...e }) => ({ ...e }));
    if (scene.length > 1 || scene.some((e) => !e.visible || e.color !== null || !isIdentity(e))) state.scene = scene;
    if (scenePanes) state.panes = true;
    const f = app.kinds.field.drawn();
    if (f && f.meshId === meshId) state.field = { job: f.jobId, artifact: f.artifact, map: f.map, range: f.range };
    // Never the token: it stays in this browser's storage (api/auth.ts).
    const url = `${location.origin}${location.pathname}${location.search}${encodeViewHash(state)}`;
    history.replaceState(null, '', url);
    display.showLink(url);
    hooks.lastLink = url;
    navigator.clipboard?.writeText(url).then(
      () => this.ctx.notice('View link copied.'),
      () => this.ctx.notice('View link: copy it from the Display panel.'),
    );
  }

  /** Opens the view of the page's #view= link, if any: its mesh, display, overlays and field, then its camera. */
  async restore(): Promise<void> {
    const { store, display, viewer, hooks, app } = this.ctx;
    let state: ViewState | null;
    try {
      state = decodeViewHash(location.hash);
    } catch (e) {
      hooks.viewRestored = { error: describe(e) };
      return this.ctx.error(`Cannot open the view link: ${describe(e)}`);
    }
    if (!state) return;
    if (!app.meshes.mesh(state.mesh)) {
      const error = `the mesh ${state.mesh} of the view link no longer exists`;
      hooks.viewRestored = { error };
      return this.ctx.error(`Cannot open the view link: ${error}`);
    }
    let scene: SceneObjectState[] = [];
    try {
      scene = state.scene ? sanitizeScene(state.scene) : [];
    } catch (e) {
      hooks.viewRestored = { error: describe(e) };
      return this.ctx.error(`Cannot open the view link: ${describe(e)}`);
    }
    app.meshes.select(state.mesh);
    if (scene[0]) app.scene.change(0, scene[0]);
    await app.loader.showing;
    const missing = scene.slice(1).filter((o) => !app.meshes.mesh(o.mesh));
    if (missing.length) this.ctx.error(`The view link's meshes ${missing.map((o) => o.mesh).join(', ')} no longer exist; the scene is shown without them.`);
    await Promise.all(
      scene
        .slice(1)
        .filter((o) => !missing.includes(o))
        .map((o) => app.scene.add(o.mesh, o)),
    );
    display.restore(state.display, state.overlays);
    if (state.field) {
      const field = app.kinds.field;
      field.chooseMap(state.field.map);
      await field.show(state.field.job, state.field.artifact);
      field.setRange(state.field.range);
    }
    if (state.panes && store.get().scene.length > 1) app.scene.sideBySide();
    applyCamera(viewer, state.camera);
    const mode = display.state().display.mode;
    viewer.redraw(() => (hooks.viewRestored = { camera: readCamera(viewer), mode }));
  }
}
