// Uploading: a file picker, and files dropped anywhere on the page.  A mesh
// chosen together with its MTL and images, or a .gltf with its .bin and
// images, goes up as one zip (the server unpacks it: README "Textured
// meshes"); which files go together is api/data_files.ts's groupUploads.
// Data other tools made (voxel grids, skeletons, a field's values:
// api/data_files.ts) goes up on its own.
import { zipSync } from 'three/examples/jsm/libs/fflate.module.js';
import { COMPANION_EXTENSIONS, DATA_EXTENSIONS, groupUploads } from '../api/data_files.ts';
import { meshFormats, type MeshFormatInfo } from '../api/rest.ts';

/** What the file picker offers: the server's mesh formats, a zip of one with its companions, the companions, and data files. */
export function acceptedExtensions(formats: readonly MeshFormatInfo[]): string[] {
  return [...formats.flatMap((f) => f.extensions), '.zip', ...COMPANION_EXTENSIONS, ...DATA_EXTENSIONS];
}

/**
 * What to upload for the mesh files chosen together (groupUploads): each
 * mesh file (or zip) alone, or zipped with its companions (named after the
 * mesh); and what was chosen that no mesh takes, a sentence each.
 */
export async function uploadsOf(files: File[]): Promise<{ uploads: Array<{ name: string; body: Blob }>; problems: string[] }> {
  const byName = new Map(files.map((f) => [f.name, f]));
  const { groups, problems } = groupUploads(files.map((f) => f.name));
  const bytes = new Map<string, Promise<Uint8Array>>();
  const read = (name: string) => {
    if (!bytes.has(name))
      bytes.set(
        name,
        byName
          .get(name)!
          .arrayBuffer()
          .then((b) => new Uint8Array(b)),
      );
    return bytes.get(name)!;
  };
  const uploads = await Promise.all(
    groups.map(async ({ mesh, companions }) => {
      const file = byName.get(mesh)!;
      if (!companions.length) return { name: mesh, body: file as Blob };
      const entries: Record<string, Uint8Array> = {};
      for (const name of [mesh, ...companions]) entries[name] = await read(name);
      const zip = zipSync(entries, { level: 0 });
      const dot = mesh.lastIndexOf('.');
      const stem = (dot > 0 ? mesh.slice(0, dot) : '') || mesh;
      return { name: `${stem}.zip`, body: new Blob([zip], { type: 'application/zip' }) };
    }),
  );
  return { uploads, problems };
}

export class UploadControl {
  constructor(input: HTMLInputElement, dropTarget: HTMLElement, onFiles: (files: File[]) => void) {
    // The server lists its formats (GET /api/v1/formats); till it has, and
    // where it cannot be asked yet (not signed in), the picker offers any
    // file and the server's answer says what it cannot read.
    const learn = () =>
      meshFormats().then(
        (formats) => (input.accept = acceptedExtensions(formats).join(',')),
        () => undefined,
      );
    void learn();
    input.addEventListener('click', () => {
      if (!input.accept) void learn();
    });
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
