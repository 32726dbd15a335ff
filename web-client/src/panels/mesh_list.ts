// The list of stored meshes: a thumbnail rendered by the server (render.png),
// name, vertex and face counts; a click shows the mesh (alone), "+" (or a
// ctrl-click) adds it to
// the scene beside the meshes shown, the delete button removes it from the
// server, the share button (⇪) opens the share form (on what the user may
// change: their own meshes, or any for an admin); another user's mesh (a
// student's, shared with their teacher) says whose it is. Meshes of one
// name (two uploads of bunny.off) are told apart by a tag: the upload time,
// with the id's start where that is the same (panels/mesh_names.ts).
import { setImageSource } from '../api/auth.ts';
import { renderUrl } from '../api/rest.ts';
import type { Mesh } from '../api/types.ts';
import { el, localTime } from './dom.ts';
import { repeatedNameTags } from './mesh_names.ts';

/** Thumbnails are rendered at 96 px and shown at 48 CSS px (sharp on high-DPI screens). */
const THUMBNAIL_PX = 96;

/** How long a delete waits at most for the mesh's thumbnail (its render may queue behind others on a busy server). */
const THUMBNAIL_WAIT_MS = 20000;

/** Whether a thumbnail's request is still on its way (with a token, it has no src until its blob arrives). */
function onItsWay(img: HTMLImageElement): boolean {
  return !img.complete || img.dataset.fetching !== undefined;
}

/**
 * Resolves once the thumbnail has arrived or failed, or after `ms`. The
 * server renders it from the stored mesh, so a render still on its way
 * answers 404 once the mesh is deleted (taking the src away does not stop
 * the request in Chromium). Thumbnails are asked for at once, not lazily, so
 * that one not yet arrived is always one on its way: a lazy image not yet in
 * view cannot be told from one whose request is queued.
 */
function imageSettled(img: HTMLImageElement | null, ms: number): Promise<void> {
  if (!img || !img.isConnected || !onItsWay(img)) return Promise.resolve();
  return new Promise((resolve) => {
    const done = (): void => resolve();
    img.addEventListener('load', done, { once: true });
    img.addEventListener('error', done, { once: true });
    setTimeout(done, ms);
  });
}

export interface MeshListActions {
  select(id: string): void;
  /** Shows the mesh beside those shown (the scene). */
  addToScene(id: string): void;
  remove(id: string): void;
  share(id: string): void;
  /** Whether the user may share (and delete) a mesh of that owner. */
  mayChange(owner: string | undefined): boolean;
  /** The owner to name beside a mesh: another user's (not the samples' system), else null. */
  ownerName?(owner: string | undefined): string | null;
}

export class MeshListPanel {
  private readonly root: HTMLElement;
  private readonly actions: MeshListActions;
  /** Each mesh's thumbnail, kept across re-renders so that it is rendered and fetched once (null: it failed). */
  private readonly thumbs = new Map<string, HTMLImageElement | null>();

  constructor(root: HTMLElement, actions: MeshListActions) {
    this.root = root;
    this.actions = actions;
  }

  render(meshes: readonly Mesh[], selectedId: string | null, inScene: ReadonlySet<string> = new Set()): void {
    // A mesh gone from the list drops its thumbnail, unless the thumbnail is
    // still on its way: were the mesh listed again meanwhile, a second
    // request would be sent that no delete waits for (imageSettled), and
    // answer 404 after it.
    for (const [id, img] of this.thumbs) if (!meshes.some((m) => m.id === id) && !(img && onItsWay(img))) this.thumbs.delete(id);
    if (meshes.length === 0) {
      this.root.replaceChildren(el('p', { class: 'empty' }, 'No meshes yet. Upload one, or drop a file on the page.'));
      return;
    }
    const tags = repeatedNameTags(meshes);
    const items = meshes.map((mesh) => {
      const tag = tags.get(mesh.id);
      // What its buttons call it: with its tag where another mesh has its name.
      const called = tag ? `${mesh.name} (${tag})` : mesh.name;
      const counts = mesh.points ? `${mesh.report.vertices} points` : `${mesh.report.vertices} V · ${mesh.report.faces} F`;
      const owner = this.actions.ownerName?.(mesh.owner) ?? null;
      const remove = el('button', { class: 'delete', type: 'button', title: `Delete ${called}`, 'aria-label': `Delete ${called}` }, '✕');
      const thumb = this.thumbnail(mesh.id);
      const add = el('button', { class: 'add-to-scene', type: 'button', title: `Add ${called} to the scene`, 'aria-label': `Add ${called} to the scene` }, '+');
      add.addEventListener('click', (ev) => {
        ev.stopPropagation();
        this.actions.addToScene(mesh.id);
      });
      let share: HTMLButtonElement | null = null;
      if (this.actions.mayChange(mesh.owner)) {
        share = el('button', { class: 'share', type: 'button', title: `Share ${called}`, 'aria-label': `Share ${called}` }, '⇪');
        share.addEventListener('click', (ev) => {
          ev.stopPropagation();
          this.actions.share(mesh.id);
        });
      }
      remove.addEventListener('click', (ev) => {
        ev.stopPropagation();
        remove.disabled = true;
        remove.closest('li')?.classList.add('deleting');
        void imageSettled(thumb, THUMBNAIL_WAIT_MS).then(() => this.actions.remove(mesh.id));
      });
      const item = el(
        'li',
        {
          class: ['mesh', mesh.id === selectedId ? 'selected' : '', inScene.has(mesh.id) ? 'in-scene' : ''].filter(Boolean).join(' '),
          'data-mesh-id': mesh.id,
          tabindex: '0',
          role: 'button',
          title: tag ? `${mesh.name} (${mesh.format}), uploaded ${localTime(mesh.created)}, id ${mesh.id}` : `${mesh.name} (${mesh.format})`,
        },
        ...(thumb ? [thumb] : []),
        // The name is cut with an ellipsis in a narrow sidebar: its own tooltip gives it whole.
        el('span', { class: 'mesh-name', title: mesh.name }, mesh.name),
        // Beside the counts, which two uploads of one file share: what tells them apart.
        el(
          'span',
          { class: 'mesh-counts' },
          counts,
          tag ? el('span', { class: 'mesh-tag', title: `Uploaded ${localTime(mesh.created)}, id ${mesh.id}` }, ` · ${tag}`) : null,
          owner ? el('span', { class: 'mesh-owner', title: `${owner}'s` }, ` · ${owner}`) : null,
        ),
        add,
        share,
        remove,
      );
      // Ctrl-click (⌘-click) adds to the scene, as "+" does.
      item.addEventListener('click', (ev) => (ev.ctrlKey || ev.metaKey ? this.actions.addToScene(mesh.id) : this.actions.select(mesh.id)));
      item.addEventListener('keydown', (ev) => {
        if (ev.key === 'Enter' || ev.key === ' ') {
          ev.preventDefault();
          this.actions.select(mesh.id);
        }
      });
      return item;
    });
    this.root.replaceChildren(el('ul', { class: 'mesh-list' }, ...items));
  }

  private thumbnail(id: string): HTMLImageElement | null {
    let thumb = this.thumbs.get(id);
    if (thumb === undefined) {
      const img = el('img', {
        class: 'mesh-thumb',
        alt: '',
        decoding: 'async',
        width: '48',
        height: '48',
      });
      // A server that cannot render (no EGL) leaves the list as it was.
      img.addEventListener('error', () => {
        img.remove();
        if (this.thumbs.has(id)) this.thumbs.set(id, null);
      });
      setImageSource(img, renderUrl(id, { width: THUMBNAIL_PX, height: THUMBNAIL_PX }));
      this.thumbs.set(id, img);
      thumb = img;
    }
    return thumb;
  }
}
