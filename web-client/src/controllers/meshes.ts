// The stored meshes: the list (kept up to date from the server's mesh_*
// events), choosing the one shown, uploads (data files among them go to the
// jobs controller as imports), deletes and sharing. The mesh list and the
// report panel render from the state. A delete takes the mesh away at once
// and offers "Undo" for a few seconds (controllers/undo.ts); the server is
// asked to delete it only then. A file whose content the user already has is
// not stored again: the mesh they have is shown. Over an empty view, the
// first screen offers samples and the file picker.
import { dataKindOf, type DataKind } from '../api/data_files.ts';
import { deleteMesh, listMeshes, uploadMesh } from '../api/rest.ts';
import { jobMeshId, type Job, type Mesh } from '../api/types.ts';
import { byId } from '../panels/dom.ts';
import { FirstScreen, samplesOf } from '../panels/first_screen.ts';
import { MeshListPanel } from '../panels/mesh_list.ts';
import { ReportPanel } from '../panels/report.ts';
import { openShareForm } from '../panels/share.ts';
import { uploadsOf } from '../panels/upload.ts';
import { selectedMesh } from '../state/app_state.ts';
import { describe, isUnauthorized, type AppContext, meshOf } from './context.ts';
import type { MeshLoader } from './mesh_loader.ts';
import type { SceneController } from './scene.ts';

/**
 * What the mesh list uses of the others: the scene it starts and the loader,
 * made before it; the comparison and the kinds it ends and the jobs that
 * import data files are made after it (they use the mesh list), so they are
 * called back.
 */
export interface MeshesDeps {
  scene: Pick<SceneController, 'add' | 'start' | 'clear' | 'isResult' | 'removeMesh'>;
  loader: Pick<MeshLoader, 'abort' | 'forgetPly' | 'ply' | 'show'>;
  /** Leaves the comparison, if one is shown. */
  leaveComparison(): void;
  /** What the artifact kinds drew on the mesh shown goes. */
  disposeKinds(): void;
  /** Imports another tool's data file for the mesh shown (an import job). */
  importFile(file: File, kind: DataKind): Promise<void>;
}

/** The server refuses names of more than 255 bytes, or with '/', '\\' or control characters. */
export function uploadName(name: string): string {
  let n = name.replace(/[\u0000-\u001f\u007f/\\]/g, '-');
  const bytes = (t: string) => new TextEncoder().encode(t).length;
  if (bytes(n) > 255) {
    while (bytes(`${n}…`) > 255) n = n.slice(0, -1);
    n = `${n}…`;
  }
  return n;
}

/** The SHA-256 of the bytes in hex, as a Mesh's sha256; null where the page has no WebCrypto (plain http off localhost). */
async function sha256Hex(body: Blob | ArrayBuffer): Promise<string | null> {
  const subtle = globalThis.crypto?.subtle;
  if (!subtle) return null;
  const digest = new Uint8Array(await subtle.digest('SHA-256', body instanceof Blob ? await body.arrayBuffer() : body));
  return Array.from(digest, (b) => b.toString(16).padStart(2, '0')).join('');
}

export class MeshesController {
  private readonly ctx: AppContext;
  /** What of the other controllers this one uses. */
  private readonly deps: MeshesDeps;
  private readonly list: MeshListPanel;
  /** Meshes deleted here whose DELETE is held back or on its way: the server's list still has them, the page does not. */
  private readonly deleting = new Set<string>();
  /**
   * The meshes this page uploaded, by the SHA-256 of the bytes it sent: a
   * zip's differs from its mesh's (the sha256 the server keeps), so the
   * same zip again is found here.
   */
  private readonly sent = new Map<string, string>();
  private readonly first: FirstScreen;
  /** Whether the server's list has come once: till then the first screen would offer no samples. */
  private listed = false;

  constructor(ctx: AppContext, deps: MeshesDeps) {
    this.ctx = ctx;
    this.deps = deps;
    this.list = new MeshListPanel(byId('mesh-list'), {
      select: (id) => this.select(id),
      addToScene: (id) => void deps.scene.add(id),
      remove: (id) => this.remove(id),
      share: (id) => openShareForm('meshes', id, this.mesh(id)?.name ?? id),
      mayChange: (owner) => ctx.account.mayChange(owner),
      ownerName: (owner) => ctx.account.otherOwner(owner),
    });
    const report = new ReportPanel(byId('report'));
    report.render(null);
    const { store } = ctx;
    // The share buttons depend on who asks; the "in scene" marks on the scene.
    store.subscribe(
      (s) => [s.meshes, s.selectedId, s.scene.map((e) => e.mesh).join(' '), s.me?.user, s.me?.admin],
      () => this.renderList(),
    );
    store.subscribe(selectedMesh, (mesh) => report.render(mesh));
    this.first = new FirstScreen(byId('viewport'), {
      show: (id) => this.select(id),
      upload: () => byId<HTMLInputElement>('file-input').click(),
    });
    store.subscribe(
      (s) => [s.meshes, s.scene.length === 0],
      () => this.renderFirst(),
    );
  }

  mesh(id: string): Mesh | null {
    return meshOf(this.ctx, id);
  }

  selected(): Mesh | null {
    return selectedMesh(this.ctx.store.get());
  }

  /** Reloads the mesh list from the server. */
  async refresh(): Promise<void> {
    const { store } = this.ctx;
    try {
      const meshes = (await listMeshes()).filter((m) => !this.deleting.has(m.id));
      store.update({ meshes });
      const id = store.get().selectedId;
      if (id && !meshes.some((m) => m.id === id)) this.forget(id);
    } catch (e) {
      this.renderList();
      if (!isUnauthorized(e)) this.ctx.error(`Cannot list meshes: ${describe(e)}`);
    } finally {
      this.listed = true;
      this.renderFirst();
    }
  }

  /**
   * Uploads files one after the other (a mesh with its MTL and images, or a
   * .gltf with its .bin and images, as one zip: groupUploads) and shows the last mesh uploaded; then the data files among them
   * (voxel grids, skeletons, a field's values: api/data_files.ts), each for
   * the mesh shown then, so that a mesh dropped with its data gets it.
   */
  async upload(files: File[]): Promise<void> {
    const { progress } = this.ctx;
    let last: Mesh | null = null;
    let uploads: Array<{ name: string; body: Blob }> = [];
    const data = files.filter((f) => dataKindOf(f.name) !== null);
    try {
      const { uploads: made, problems } = await uploadsOf(files.filter((f) => dataKindOf(f.name) === null));
      uploads = made;
      for (const p of problems) this.ctx.error(`Not uploaded: ${p}.`);
    } catch (e) {
      this.ctx.error(`Upload failed: ${describe(e)}`);
    }
    for (const file of uploads) {
      progress.show('uploading', null, file.name);
      try {
        const { mesh, known } = await this.findOrUpload(file.name, file.body);
        if (known) this.ctx.notice(`${file.name}: already uploaded as ${mesh.name}.`);
        else for (const w of mesh.warnings ?? []) this.ctx.warning(`${mesh.name}: ${w}`);
        last = mesh;
      } catch (e) {
        this.ctx.error(`Upload of ${file.name} failed: ${describe(e)}`);
      } finally {
        progress.hide();
      }
    }
    if (last) this.select(last.id);
    for (const file of data) await this.deps.importFile(file, dataKindOf(file.name)!);
  }

  /**
   * The user's mesh of this content (`known`), or the mesh the upload made.
   * Where the page cannot hash (no WebCrypto), the server's sha256 of the
   * new mesh tells a twin, which is deleted again; a zip is told only by its
   * own bytes, as the same mesh may come with other images.
   */
  private async findOrUpload(name: string, body: Blob | ArrayBuffer, format?: string): Promise<{ mesh: Mesh; known: boolean }> {
    const hash = await sha256Hex(body);
    const known = hash ? (this.ownWithContent(hash) ?? this.mesh(this.sent.get(hash) ?? '')) : null;
    if (known) return { mesh: known, known: true };
    const mesh = await uploadMesh(name, body, format);
    if (hash) this.sent.set(hash, mesh.id);
    const zip = format === 'zip' || (!format && /\.zip$/i.test(name));
    const twin = !hash && !zip && mesh.sha256 ? this.ownWithContent(mesh.sha256, mesh.id) : null;
    if (!twin) {
      this.upsert(mesh);
      return { mesh, known: false };
    }
    this.deleting.add(mesh.id);
    this.forget(mesh.id); // its mesh_added event may have come first
    void deleteMesh(mesh.id)
      .catch(() => {})
      .finally(() => this.deleting.delete(mesh.id));
    return { mesh: twin, known: true };
  }

  /** The user's own mesh (not a sample, not another's shared) whose stored file has this SHA-256. */
  private ownWithContent(sha256: string, except?: string): Mesh | null {
    const { meshes, me } = this.ctx.store.get();
    const own = (m: Mesh) => (me ? m.owner === me.user : m.owner !== 'system');
    return meshes.find((m) => m.sha256 === sha256 && m.id !== except && own(m)) ?? null;
  }

  /** Shows the mesh alone: the scene starts again from it, and what was drawn on the last one goes. */
  select(id: string): void {
    const mesh = this.mesh(id);
    if (!mesh) return;
    const { store } = this.ctx;
    const { deps } = this;
    store.update({ selectedId: id });
    deps.leaveComparison();
    deps.scene.start(mesh);
    store.update({ runTarget: null, inputName: mesh.name });
    this.ctx.selectionTool.setSource(id, (meshId) => deps.loader.ply(meshId));
    deps.disposeKinds(); // what the kinds drew on the last mesh
    deps.loader.show(mesh);
  }

  /** Selects the mesh a job ran on (when it is another one, and still stored), so that what the job made is drawn on it. */
  selectMeshOf(job: Job): void {
    const meshId = jobMeshId(job);
    if (meshId && this.ctx.store.get().selectedId !== meshId && this.mesh(meshId)) this.select(meshId);
  }

  /**
   * Takes the mesh away (from the list, the view and the scene) and offers
   * it back for a few seconds; then deletes it on the server. Undone, it
   * comes back as it was shown: alone or with the scene around it, or beside
   * the mesh shown.
   */
  remove(id: string): void {
    const mesh = this.mesh(id);
    if (!mesh) return;
    const { store } = this.ctx;
    const { deps } = this;
    const shown = store.get().selectedId === id;
    const scene = store.get().scene.map(({ object: _, ...entry }) => entry);
    this.deleting.add(id);
    this.forget(id);
    this.ctx.undo.offer(`Deleted ${mesh.name}.`, {
      undo: () => {
        this.deleting.delete(id);
        this.upsert(mesh);
        const now = store.get().scene;
        if (shown && !store.get().selectedId) {
          this.select(id);
          for (const entry of scene.slice(1)) if (this.mesh(entry.mesh) || deps.scene.isResult(entry.mesh)) void deps.scene.add(entry.mesh, entry);
        } else if (now.length && now[0]!.mesh === scene[0]?.mesh) {
          for (const entry of scene.slice(1)) if (entry.mesh === id) void deps.scene.add(id, entry);
        }
      },
      commit: () => void this.destroy(id, mesh.name),
    });
  }

  /** Deletes the mesh on the server; one that could not be deleted comes back into the list. */
  private async destroy(id: string, name: string): Promise<void> {
    try {
      await deleteMesh(id);
    } catch (e) {
      this.ctx.error(`Cannot delete ${name}: ${describe(e)}`);
      this.deleting.delete(id);
      await this.refresh();
    } finally {
      this.deleting.delete(id);
    }
  }

  /** A mesh added or changed on the server. */
  upsert(mesh: Mesh): void {
    if (this.deleting.has(mesh.id)) return;
    this.deps.loader.forgetPly(mesh.id);
    this.ctx.store.update((s) => {
      const i = s.meshes.findIndex((m) => m.id === mesh.id);
      return { meshes: i >= 0 ? s.meshes.map((m, k) => (k === i ? mesh : m)) : [...s.meshes, mesh] };
    });
  }

  /** Drops a mesh that no longer exists on the server; clears the view if it was shown. */
  forget(id: string): void {
    const { store, viewer, hooks } = this.ctx;
    const { deps } = this;
    store.update((s) => ({ meshes: s.meshes.filter((m) => m.id !== id) }));
    deps.scene.removeMesh(id);
    deps.loader.forgetPly(id);
    if (store.get().selectedId !== id) return;
    store.update({ selectedId: null, inputName: null });
    this.ctx.selectionTool.setSource(null, (meshId) => deps.loader.ply(meshId));
    deps.leaveComparison();
    deps.disposeKinds();
    deps.loader.abort(id);
    viewer.clearAll();
    this.ctx.textures.detach();
    hooks.lastLoaded = null;
    hooks.timings = null;
    deps.scene.clear();
  }

  /** The first screen over an empty view, once the list (and so the samples) has come. */
  private renderFirst(): void {
    const s = this.ctx.store.get();
    this.first.render(samplesOf(s.meshes), this.listed && s.scene.length === 0);
  }

  private renderList(): void {
    const s = this.ctx.store.get();
    this.list.render(s.meshes, s.selectedId, new Set(s.scene.map((e) => e.mesh)));
  }
}
