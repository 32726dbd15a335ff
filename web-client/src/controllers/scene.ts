// The scene: several meshes at once. The selected mesh comes first (whatever
// the viewer shows for it: its surface, a field on it, an animation), then
// the meshes added beside it with "+", each with its visibility, colour and
// transform; side by side, one per pane, on demand. An object taken out with
// the Scene panel's ✕ is offered back for a few seconds.
import type * as THREE from 'three';
import type { Mesh } from '../api/types.ts';
import { byId } from '../panels/dom.ts';
import { ScenePanel } from '../panels/scene.ts';
import type { SceneEntry } from '../state/app_state.ts';
import type { TestHooks } from '../test_hooks.ts';
import { applySceneTransform, projectedBox } from '../viewer/scene_objects.ts';
import { defaultSceneObject, MAX_SCENE_OBJECTS, sceneColor, type SceneObjectState } from '../viewer/scene_state.ts';
import { buildSurface } from '../viewer/surface_renderer.ts';
import { LoadTimer } from '../viewer/timings.ts';
import { describe, type AppContext } from './context.ts';

export class SceneController {
  private readonly ctx: AppContext;

  constructor(ctx: AppContext) {
    this.ctx = ctx;
    const panel = new ScenePanel(byId('scene'), {
      change: (i, patch) => this.change(i, patch),
      remove: (i) => this.removeWithUndo(i),
      fitAll: () => ctx.viewer.fitAll(),
      pick: (i) => this.pick(i),
      sideBySide: (on) => (on ? this.sideBySide() : ctx.app.compare.leaveWithUndo()),
    });
    ctx.store.subscribe(
      (s) => [s.scene, s.scenePanes, s.picked],
      () => {
        const s = ctx.store.get();
        panel.render(s.scene, s.scenePanes, ctx.display.state().display.color, s.picked);
      },
    );
  }

  private get entries(): readonly SceneEntry[] {
    return this.ctx.store.get().scene;
  }

  /** A new scene of the mesh alone (the mesh just selected). */
  start(mesh: Mesh): void {
    this.ctx.store.update({ scene: [{ ...defaultSceneObject(mesh.id), name: mesh.name, object: null }] });
    this.pick(0);
  }

  /** No scene: nothing is shown. */
  clear(): void {
    this.ctx.store.update({ scene: [], scenePanes: false });
  }

  /** Takes the mesh's objects (but the first) out of the scene: the mesh is gone. */
  removeMesh(meshId: string): void {
    for (let i = this.entries.length - 1; i > 0; --i) if (this.entries[i]!.mesh === meshId) this.remove(i);
  }

  /**
   * "+" in the mesh list: draws the mesh beside the scene's objects, in the
   * next colour and the display mode of the others (with nothing shown, it
   * is shown as a click would). `state` (a view link's) gives its visibility,
   * colour and transform. Resolves once it is drawn (or has failed).
   */
  async add(id: string, state?: SceneObjectState): Promise<void> {
    const { app, store, display, viewer, progress } = this.ctx;
    const mesh = app.meshes.mesh(id);
    if (!mesh) return;
    if (!this.entries.length) {
      app.meshes.select(id);
      return;
    }
    if (this.entries.length >= MAX_SCENE_OBJECTS) return this.ctx.error(`A scene holds at most ${MAX_SCENE_OBJECTS} objects.`);
    const entry: SceneEntry = { ...(state ?? defaultSceneObject(id, sceneColor(this.entries.length - 1))), mesh: id, name: mesh.name, object: null };
    store.update((s) => ({ scene: [...s.scene, entry] }));
    const inScene = () => this.entries.includes(entry);
    try {
      await app.loader.showing; // the first object's show() clears the viewer's extras
      if (!inScene()) return;
      const controller = new AbortController();
      const loaded = await app.loader.downloadMesh(mesh, controller.signal, inScene, new LoadTimer());
      progress.hide();
      if (!loaded || !inScene()) return;
      const object = buildSurface(loaded.decoded);
      object.name = `scene:${mesh.name}`;
      entry.object = object;
      applySceneTransform(object, entry);
      display.applyTo(object);
      if (this.entries[store.get().picked] === entry) display.setOverlayObject(object);
      await new Promise<void>((resolve) => viewer.addExtra(object, resolve));
      if (store.get().scenePanes) this.sideBySide();
    } catch (e) {
      progress.hide();
      if (!inScene()) return;
      store.update((s) => ({ scene: s.scene.filter((e) => e !== entry) }));
      this.ctx.error(`Cannot add ${mesh.name} to the scene: ${describe(e)}`);
    }
  }

  /** The drawn object of scene entry `index` (the first: whatever the viewer shows for the selected mesh). */
  object(index: number): THREE.Object3D | null {
    return index === 0 ? this.ctx.viewer.object : (this.entries[index]?.object ?? null);
  }

  entryOf(object: THREE.Object3D): SceneEntry | null {
    const i = this.entries.findIndex((_, k) => this.object(k) === object);
    return i >= 0 ? this.entries[i]! : null;
  }

  /** The objects beside the first that are drawn. */
  others(): THREE.Object3D[] {
    return this.entries.slice(1).flatMap((e) => (e.object ? [e.object] : []));
  }

  /** A new shown object (the selected mesh, its field, an animation) takes the first scene object's place and transform. */
  shownChanged(object: THREE.Object3D | null): void {
    const first = this.entries[0];
    if (object && first && first.mesh === this.ctx.store.get().selectedId) applySceneTransform(object, first);
  }

  /** Changes an object's state (the panel's controls edit the entry in place: it does not render again). */
  change(index: number, patch: Partial<SceneObjectState>): void {
    const entry = this.entries[index];
    if (!entry) return;
    Object.assign(entry, patch);
    const object = this.object(index);
    if (object) {
      applySceneTransform(object, entry);
      if (patch.color !== undefined) this.ctx.display.applyTo(object);
      if (index === this.ctx.store.get().picked) this.ctx.display.refreshOverlays();
    }
    this.ctx.viewer.requestRender();
  }

  remove(index: number): void {
    const { store, app, viewer } = this.ctx;
    const entry = this.entries[index];
    if (!entry || index === 0) return;
    store.update((s) => ({ scene: s.scene.filter((e) => e !== entry) }));
    const picked = store.get().picked;
    if (index === picked) this.pick(0);
    else if (index < picked) store.update({ picked: picked - 1 });
    const wasPanes = store.get().scenePanes;
    if (wasPanes) app.compare.leave();
    if (entry.object) viewer.removeExtra(entry.object);
    if (wasPanes && this.entries.length >= 2) this.sideBySide();
  }

  /** The Scene panel's ✕: takes the object out and offers it back, with its colour and transform, for a few seconds. */
  private removeWithUndo(index: number): void {
    const entry = this.entries[index];
    if (!entry || index === 0) return;
    const first = this.entries[0]!.mesh;
    const { object: _, ...state } = entry;
    this.remove(index);
    this.ctx.undo.offer(`${entry.name} removed from the scene.`, {
      undo: () => {
        if (this.entries[0]?.mesh === first && this.ctx.app.meshes.mesh(state.mesh)) void this.add(state.mesh, state);
      },
    });
  }

  /** The scene's objects side by side, one per pane, all through the one camera; framed together. */
  sideBySide(): void {
    const color = this.ctx.display.state().display.color;
    const items = this.entries.flatMap((e, i) => {
      const object = this.object(i);
      return object ? [{ key: `scene:${i}`, title: e.name, object, color: e.color ?? color }] : [];
    });
    if (items.length < 2) return this.ctx.error('Side by side needs two objects in the scene: add one with “+” in the mesh list.');
    this.ctx.app.compare.showScene(items);
    this.ctx.store.update({ scenePanes: true });
    this.ctx.viewer.fitAll();
  }

  /** Chooses scene object `index` for the overlays (the first: the shown object, whatever it is). */
  pick(index: number): void {
    if (!this.entries[index]) index = 0;
    this.ctx.store.update({ picked: index });
    this.ctx.display.setOverlayObject(index === 0 ? null : this.object(index));
  }

  /** The scene as the frame drew it, for the test hooks. */
  report(): TestHooks['scene'] {
    const { viewer, store } = this.ctx;
    // Drawn per pane with the pane's aspect (viewer.resize), or over the canvas.
    const objects = this.entries.map((e, i) => {
      const object = this.object(i);
      const pane = object ? viewer.paneOf(object) : -1;
      const { name, object: _, ...state } = e;
      return {
        ...state,
        position: [...e.position] as SceneObjectState['position'],
        rotation: [...e.rotation] as SceneObjectState['rotation'],
        name,
        loaded: !!object,
        pane,
        box: object ? projectedBox(object, viewer.camera) : null,
      };
    });
    return { panes: store.get().scenePanes ? objects.filter((o) => o.pane >= 0).length : 0, picked: store.get().picked, objects };
  }
}
