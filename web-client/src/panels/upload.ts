// Uploading: a file picker, and files dropped anywhere on the page.  A mesh
// chosen together with its MTL and images goes up as one zip (the server
// unpacks it: README "Textured meshes"); data other tools made (voxel grids,
// skeletons, a field's values: api/data_files.ts) goes up on its own.
import { zipSync } from 'three/examples/jsm/libs/fflate.module.js';
import { DATA_EXTENSIONS } from '../api/data_files.ts';

export const ACCEPTED = ['.off', '.obj', '.ply', '.stl', '.drc', '.glb', '.gltf', '.zip', '.mtl', '.png', '.jpg', '.jpeg', ...DATA_EXTENSIONS];
/** Files that go with a mesh rather than being one. */
const COMPANIONS = ['.mtl', '.png', '.jpg', '.jpeg'];

function extension(name: string): string {
  const dot = name.lastIndexOf('.');
  return dot < 0 ? '' : name.slice(dot).toLowerCase();
}

/**
 * What to upload for the files chosen together: each mesh file (or zip)
 * alone, or, when MTLs or images come with it, a zip of the mesh and all
 * of them (named after the mesh). Throws when only companions were chosen.
 */
export async function uploadsOf(files: File[]): Promise<Array<{ name: string; body: Blob }>> {
  const companions = files.filter((f) => COMPANIONS.includes(extension(f.name)));
  const meshes = files.filter((f) => !COMPANIONS.includes(extension(f.name)));
  if (!companions.length) return meshes.map((f) => ({ name: f.name, body: f }));
  if (!meshes.length) throw new Error(`${companions.map((f) => f.name).join(', ')}: choose the mesh file with its materials and images`);
  const companionBytes = await Promise.all(companions.map(async (f) => [f.name, new Uint8Array(await f.arrayBuffer())] as const));
  return Promise.all(
    meshes.map(async (mesh) => {
      if (extension(mesh.name) === '.zip') return { name: mesh.name, body: mesh as Blob };
      const entries: Record<string, Uint8Array> = { [mesh.name]: new Uint8Array(await mesh.arrayBuffer()) };
      for (const [name, bytes] of companionBytes) entries[name] = bytes;
      const zip = zipSync(entries, { level: 0 });
      const stem = mesh.name.slice(0, mesh.name.length - extension(mesh.name).length) || mesh.name;
      return { name: `${stem}.zip`, body: new Blob([zip], { type: 'application/zip' }) };
    }),
  );
}

export class UploadControl {
  constructor(input: HTMLInputElement, dropTarget: HTMLElement, onFiles: (files: File[]) => void) {
    input.accept = ACCEPTED.join(',');
    input.multiple = true;
    input.addEventListener('change', () => {
      const files = [...(input.files ?? [])];
      input.value = ''; // choosing the same file again fires change again
      if (files.length) onFiles(files);
    });

    // dragenter/dragleave fire for every child crossed: count them.
    let depth = 0;
    const hasFiles = (ev: DragEvent) => ev.dataTransfer?.types.includes('Files') ?? false;
    dropTarget.addEventListener('dragenter', (ev) => {
      if (!hasFiles(ev)) return;
      ev.preventDefault();
      if (depth++ === 0) document.body.classList.add('dragging');
    });
    dropTarget.addEventListener('dragover', (ev) => {
      if (!hasFiles(ev)) return;
      ev.preventDefault();
      if (ev.dataTransfer) ev.dataTransfer.dropEffect = 'copy';
    });
    dropTarget.addEventListener('dragleave', () => {
      if (depth > 0 && --depth === 0) document.body.classList.remove('dragging');
    });
    dropTarget.addEventListener('drop', (ev) => {
      ev.preventDefault();
      depth = 0;
      document.body.classList.remove('dragging');
      const files = [...(ev.dataTransfer?.files ?? [])];
      if (files.length) onFiles(files);
    });
  }
}
