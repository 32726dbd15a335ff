// The scene: several meshes at once. The selected mesh comes first (whatever
// the viewer shows for it: its surface, a field on it, an animation), then
// the meshes added beside it with "+", each with its visibility, colour and
// transform; side by side, one per pane, on demand. An object taken out with
// the Scene panel's ✕ is offered back for a few seconds.
//
// A job's output mesh ("Add to view") is a scene object too, named after what
// it was made from ("elephant · simplify 1000"). Drawn over its source the two
// fight for the same pixels, so it goes beside it, one box width along x; the
// Scene panel puts it back "in place" to compare.
import * as THREE from 'three';
import { fetchArtifactBytes } from '../api/rest.ts';
import type { Mesh } from '../api/types.ts';
import { byId } from '../panels/dom.ts';
import { ScenePanel, type Placement, type SceneRow } from '../panels/scene.ts';
import type { SceneEntry } from '../state/app_state.ts';
import type { TestHooks } from '../test_hooks.ts';
import { parsePly } from '../viewer/ply.ts';
import { applySceneTransform, projectedBox } from '../viewer/scene_objects.ts';
import { defaultSceneObject, MAX_SCENE_OBJECTS, sceneColor, type SceneObjectState, type Vec3 } from '../viewer/scene_state.ts';
import { buildPlainSurface, buildSurface } from '../viewer/surface_renderer.ts';
import { LoadTimer } from '../viewer/timings.ts';
import { describe, jobOf, type AppContext, meshOf } from './context.ts';
import type { PaneObject } from './compare.ts';
import type { MeshLoader } from './mesh_loader.ts';

/**
 * What the scene uses of the others: the loader, made before it; the mesh
 * list, the jobs and the comparison are made after it (they use the scene),
 * so what it asks of them is called back.
 */
export interface SceneDeps {
  loader: Pick<MeshLoader, 'downloadMesh' | 'showing'>;
  /** Shows a stored mesh alone (the mesh list's select). */
  selectMesh(id: string): void;
  /** A job's output named after what it was made from ("elephant · simplify 1000"). */
  resultName(jobId: string, artifact: string): string;
  /** The stored mesh a job's output came from; null: none known. */
  sourceMeshOf(jobId: string): string | null;
  /** Leaves the comparison (the panes side by side), if one is shown. */
  leaveComparison(): void;
  /** Leaves it and offers it back for a few seconds. */
  leaveComparisonWithUndo(): void;
  /** Shows these objects side by side, one per pane. */
  showPanes(items: PaneObject[]): void;
}

/**
 * A job's output stands in the scene where a stored mesh's id would (no mesh
 * id has a colon): undo keeps it as it keeps a mesh's, and add() draws it
 * again from it.
 */
const RESULT_PREFIX = 'job:';
/** The gap between a result and its source, as a share of the source's largest side. */
const BESIDE_MARGIN = 0.25;

function resultId(jobId: string, artifact: string): string {
  return `${RESULT_PREFIX}${jobId}/${artifact}`;
}

/** The job and artifact of a result's scene id; null for a stored mesh's. */
export function resultOf(id: string): { jobId: string; artifact: string } | null {
  if (!id.startsWith(RESULT_PREFIX)) return null;
  const rest = id.slice(RESULT_PREFIX.length);
  const slash = rest.indexOf('/');
  return slash > 0 ? { jobId: rest.slice(0, slash), artifact: rest.slice(slash + 1) } : null;
}

const near = (a: readonly number[], b: readonly number[], tolerance: number) => a.every((x, i) => Math.abs(x - b[i]!) <= tolerance);

export class SceneController {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: SceneDeps;

  constructor(ctx: AppContext, deps: SceneDeps) {
    this.ctx = ctx;
    this.deps = deps;
    const panel = new ScenePanel(byId('scene'), {
      change: (i, patch) => this.change(i, patch),
      remove: (i) => this.removeWithUndo(i),
      fitAll: () => ctx.viewer.fitAll(),
      pick: (i) => this.pick(i),
      sideBySide: (on) => (on ? this.sideBySide() : deps.leaveComparisonWithUndo()),
      place: (i, where) => this.place(i, where),
    });
    ctx.store.subscribe(
      (s) => [s.scene, s.scenePanes, s.picked],
      () => {
        const s = ctx.store.get();
        panel.render(this.rows(), s.scenePanes, ctx.display.state().display.color, s.picked);
      },
    );
  }

  /** Whether a scene id is a job's output rather than a stored mesh. */
  isResult(id: string): boolean {
    return resultOf(id) !== null;
  }

  /** Whether add() can draw a scene id: a stored mesh, or the output of a job the client knows. */
  canAdd(id: string): boolean {
    const result = resultOf(id);
    return result ? jobOf(this.ctx, result.jobId) !== undefined : meshOf(this.ctx, id) !== null;
  }

  private rows(): SceneRow[] {
    return this.entries.map(({ object: _, ...e }, i) => {
      const source = this.sourceIndex(i);
      return source < 0 ? e : { ...e, source: this.entries[source]!.name, placement: this.placement(i, source) };
    });
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
    const result = resultOf(id);
    if (result) return this.addResult(result.jobId, result.artifact, state);
    const { store } = this.ctx;
    const { deps } = this;
    const mesh = meshOf(this.ctx, id);
    if (!mesh) return;
    if (!this.entries.length) {
      deps.selectMesh(id);
      return;
    }
    if (this.entries.length >= MAX_SCENE_OBJECTS) return this.ctx.error(`A scene holds at most ${MAX_SCENE_OBJECTS} objects.`);
    const entry: SceneEntry = { ...(state ?? defaultSceneObject(id, sceneColor(this.entries.length - 1))), mesh: id, name: mesh.name, object: null };
    store.update((s) => ({ scene: [...s.scene, entry] }));
    await this.draw(entry, async (inScene) => {
      const loaded = await deps.loader.downloadMesh(mesh, new AbortController().signal, inScene, new LoadTimer());
      // The scene's objects are surfaces (their mode, colour and panes): a cloud is shown alone.
      if (loaded?.decoded.points) throw new Error('it is a point cloud, shown alone (choose it in the list)');
      return loaded ? buildSurface(loaded.decoded) : null;
    });
  }

  /**
   * "Add to view" on a job's output mesh: drawn (from its PLY) as a scene
   * object of its own, in the next colour, beside its source mesh (which is
   * shown first when the scene lacks it); `state` (a view link's, an undo's)
   * gives its place instead. Resolves once it is drawn (or has failed).
   */
  async addResult(jobId: string, artifact: string, state?: SceneObjectState): Promise<void> {
    const { store, viewer, hooks } = this.ctx;
    const { deps } = this;
    const job = jobOf(this.ctx, jobId);
    const id = resultId(jobId, artifact);
    if (!job || this.entries.some((e) => e.mesh === id)) return;
    const name = deps.resultName(jobId, artifact);
    const source = deps.sourceMeshOf(jobId);
    if (!state && source && meshOf(this.ctx, source) && !this.entries.some((e) => e.mesh === source)) deps.selectMesh(source);
    if (!this.entries.length) return this.ctx.error(`Show a mesh first: ${name} is drawn beside it.`);
    if (this.entries.length >= MAX_SCENE_OBJECTS) return this.ctx.error(`A scene holds at most ${MAX_SCENE_OBJECTS} objects.`);
    const entry: SceneEntry = { ...(state ?? defaultSceneObject(id, sceneColor(this.entries.length - 1))), mesh: id, name, object: null };
    store.update((s) => ({ scene: [...s.scene, entry] }));
    let counts = { vertices: 0, faces: 0 };
    const drawn = await this.draw(
      entry,
      async () => {
        const ply = parsePly(await fetchArtifactBytes(jobId, artifact, 'ply'));
        counts = { vertices: ply.vertices, faces: ply.faces };
        return buildPlainSurface(ply.positions, ply.indices, entry.color ?? undefined);
      },
      state ? undefined : (object) => this.placeBeside(entry, object),
    );
    if (!drawn) return;
    if (!state) viewer.fitAll();
    viewer.redraw(() => (hooks.lastExtra = { jobId, artifact, ...counts }));
  }

  /** Takes a job's output out of the scene, if it is there. */
  removeResult(jobId: string, artifact: string): void {
    const i = this.entries.findIndex((e) => e.mesh === resultId(jobId, artifact));
    if (i > 0) this.remove(i);
  }

  /**
   * Draws a new entry's object once `build` has made it, after `place` has set
   * where; takes the entry out again, with an error, when it fails. Resolves
   * whether it was drawn (false too when the entry left the scene meanwhile).
   */
  private async draw(entry: SceneEntry, build: (inScene: () => boolean) => Promise<THREE.Mesh | null>, place?: (object: THREE.Mesh) => void): Promise<boolean> {
    const { store, display, viewer, progress } = this.ctx;
    const { deps } = this;
    const inScene = () => this.entries.includes(entry);
    try {
      await deps.loader.showing; // the first object's show() clears the viewer's extras
      if (!inScene()) return false;
      const object = await build(inScene);
      progress.hide();
      if (!object || !inScene()) return false;
      object.name = `scene:${entry.name}`;
      entry.object = object;
      place?.(object);
      applySceneTransform(object, entry);
      display.applyTo(object);
      if (this.entries[store.get().picked] === entry) display.setOverlayObject(object);
      await new Promise<void>((resolve) => viewer.addExtra(object, resolve));
      if (store.get().scenePanes) this.sideBySide();
      return true;
    } catch (e) {
      progress.hide();
      if (!inScene()) return false;
      store.update((s) => ({ scene: s.scene.filter((e) => e !== entry) }));
      this.ctx.error(`Cannot add ${entry.name} to the scene: ${describe(e)}`);
      return false;
    }
  }

  /** The scene index of result `index`'s source mesh (the first object's when the source is not in the scene); -1 for no result. */
  private sourceIndex(index: number): number {
    const result = resultOf(this.entries[index]?.mesh ?? '');
    if (!result) return -1;
    const source = this.deps.sourceMeshOf(result.jobId);
    const i = this.entries.findIndex((e) => e.mesh === source);
    // A source not in the scene: the result lies over the shown mesh (the job ran on what was shown then).
    return i >= 0 ? i : index > 0 ? 0 : -1;
  }

  /**
   * Where result `index` would stand beside source `source`: the source's
   * world box width (the drawn source, else the result itself) plus a margin
   * along x, turned and scaled as the source is.
   */
  private besideOf(index: number, source: number): Vec3 {
    const s = this.entries[source]!;
    const object = this.object(source) ?? this.object(index);
    const box = object ? new THREE.Box3().setFromObject(object) : new THREE.Box3();
    const size = box.isEmpty() ? new THREE.Vector3(1, 1, 1) : box.getSize(new THREE.Vector3());
    const gap = size.x + BESIDE_MARGIN * Math.max(size.x, size.y, size.z, 1e-9);
    return [s.position[0] + gap, s.position[1], s.position[2]];
  }

  /** A new result goes beside its source, turned and scaled as it is. */
  private placeBeside(entry: SceneEntry, object: THREE.Mesh): void {
    const index = this.entries.indexOf(entry);
    const source = this.sourceIndex(index);
    if (source < 0) return;
    const s = this.entries[source]!;
    Object.assign(entry, { rotation: [...s.rotation], scale: s.scale, position: [...s.position] });
    applySceneTransform(object, entry);
    entry.position = this.besideOf(index, source);
    // The panel shows where it went.
    this.ctx.store.update({ scene: [...this.entries] });
  }

  /** Whether result `index` stands over its source, beside it, or elsewhere (moved by hand). */
  private placement(index: number, source: number): Placement {
    const e = this.entries[index]!;
    const s = this.entries[source]!;
    const magnitude = Math.max(1, ...s.position.map(Math.abs));
    if (e.scale !== s.scale || !near(e.rotation, s.rotation, 1e-9)) return 'moved';
    if (near(e.position, s.position, 1e-9 * magnitude)) return 'in place';
    return near(e.position, this.besideOf(index, source), 1e-6 * magnitude) ? 'beside' : 'moved';
  }

  /** The Scene panel's "In place" / "Beside": result `index` over its source, to compare, or beside it again. */
  place(index: number, where: Exclude<Placement, 'moved'>): void {
    const source = this.sourceIndex(index);
    if (source < 0) return;
    const s = this.entries[source]!;
    this.change(index, { rotation: [...s.rotation], scale: s.scale, position: where === 'in place' ? [...s.position] : this.besideOf(index, source) });
    this.ctx.store.update({ scene: [...this.entries] });
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
    const { store, viewer } = this.ctx;
    const { deps } = this;
    const entry = this.entries[index];
    if (!entry || index === 0) return;
    store.update((s) => ({ scene: s.scene.filter((e) => e !== entry) }));
    const picked = store.get().picked;
    if (index === picked) this.pick(0);
    else if (index < picked) store.update({ picked: picked - 1 });
    const wasPanes = store.get().scenePanes;
    if (wasPanes) deps.leaveComparison();
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
        if (this.entries[0]?.mesh === first && (this.isResult(state.mesh) || meshOf(this.ctx, state.mesh))) void this.add(state.mesh, state);
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
    this.deps.showPanes(items);
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
