// Which files the upload control sends to POST /data (protocol/API.md) rather
// than to POST /meshes, and as what. The server takes the kind from the
// name's extension too, but .ply, .obj and .json are meshes as well as fields
// or skeletons: those stay mesh uploads here (what the control always did),
// and "Load skeleton file…" and "Load field file…" name the kind instead.
// And which of the mesh files chosen together go up as one zip (groupUploads):
// an OBJ with its MTL and images, a .gltf with its .bin buffers and images.
// Pure, with no imports, so that node's unit tests load it.

/** What POST /data makes of a file: the artifact kind of its import job. */
export type DataKind = 'voxel_grid' | 'skeleton' | 'scalar_field';

/** The voxel grid formats the server reads (API.md, POST /data). */
export const VOXEL_GRID_EXTENSIONS = ['.nrrd', '.binvox', '.vti', '.vox', '.vdb'];
/** The skeleton formats that are nothing else (CGAL's polylines, the mesh-contraction tools' .cg). */
export const SKELETON_EXTENSIONS = ['.polylines', '.cg'];
/** Everything the upload control takes as data: grids, skeletons, and text with one value a line. */
export const DATA_EXTENSIONS = [...VOXEL_GRID_EXTENSIONS, ...SKELETON_EXTENSIONS, '.txt'];

function extension(name: string): string {
  const dot = name.lastIndexOf('.');
  return dot < 0 ? '' : name.slice(dot).toLowerCase();
}

/**
 * The kind of data a file chosen or dropped in the upload control is, by its
 * name; null for a mesh (or a mesh's companion: an MTL, an image, a zip).
 * A .txt file is a scalar field's values, unless it is CGAL's .polylines.txt.
 */
export function dataKindOf(name: string): DataKind | null {
  const ext = extension(name);
  if (VOXEL_GRID_EXTENSIONS.includes(ext)) return 'voxel_grid';
  if (SKELETON_EXTENSIONS.includes(ext) || name.toLowerCase().endsWith('.polylines.txt')) return 'skeleton';
  if (ext === '.txt') return 'scalar_field';
  return null;
}

/** Whether POST /data needs the stored mesh the data is for: a field has a value per vertex or face of it; a skeleton is drawn over it. */
export function needsMesh(kind: DataKind): boolean {
  return kind !== 'voxel_grid';
}

/** What a file of that kind is, as an error about it says ("a skeleton"); of the kinds that need a mesh. */
export function dataKindWords(kind: DataKind): string {
  return kind === 'skeleton' ? 'a skeleton' : "a scalar field's values";
}

/** Files that go up inside a mesh's zip, never alone: an OBJ's materials, a .gltf's buffers, images. */
export const COMPANION_EXTENSIONS = ['.mtl', '.bin', '.png', '.jpg', '.jpeg'];
const IMAGE_EXTENSIONS = ['.png', '.jpg', '.jpeg'];

/** One upload: a mesh file, alone when it has no companions, else zipped with them (the zip named after the mesh). */
export interface UploadGroup {
  mesh: string;
  companions: string[];
}

function stem(name: string): string {
  return name.slice(0, name.length - extension(name).length);
}

/**
 * How mesh files chosen or dropped together go up (data files set aside
 * first: dataKindOf). Each mesh is one upload: a zip (already a bundle)
 * alone; a .gltf with the .bin buffers and images chosen with it; any other
 * mesh with the MTLs and images chosen with it. A .bin is a .gltf's and
 * nothing else's: it goes with the .gltf of the same stem when there is
 * one, else with every .gltf chosen, and never up as a mesh. `problems`
 * says, a sentence each, what was chosen that no mesh takes (a .bin without
 * its .gltf; materials or images without a mesh).
 */
export function groupUploads(names: readonly string[]): { groups: UploadGroup[]; problems: string[] } {
  const companion = (n: string) => COMPANION_EXTENSIONS.includes(extension(n));
  const meshes = names.filter((n) => !companion(n));
  const gltfs = meshes.filter((n) => extension(n) === '.gltf');
  const bins = names.filter((n) => extension(n) === '.bin');
  const images = names.filter((n) => IMAGE_EXTENSIONS.includes(extension(n)));
  const materials = names.filter((n) => extension(n) === '.mtl');
  const taken = new Set<string>();
  const groups = meshes.map((mesh): UploadGroup => {
    const ext = extension(mesh);
    let companions: string[] = [];
    if (ext === '.gltf') {
      const own = bins.filter((b) => stem(b).toLowerCase() === stem(mesh).toLowerCase());
      const unclaimed = bins.filter((b) => !gltfs.some((g) => stem(g).toLowerCase() === stem(b).toLowerCase()));
      companions = [...own, ...unclaimed, ...images];
    } else if (ext !== '.zip') {
      companions = [...materials, ...images];
    }
    for (const c of companions) taken.add(c);
    return { mesh, companions };
  });
  const problems: string[] = [];
  const loneBins = bins.filter((b) => !taken.has(b));
  if (loneBins.length) problems.push(`${loneBins.join(', ')}: a glTF buffer is not a mesh; choose it together with the .gltf that names it (and its images)`);
  const loneRest = names.filter((n) => companion(n) && extension(n) !== '.bin' && !taken.has(n));
  if (loneRest.length) problems.push(`${loneRest.join(', ')}: choose the mesh file with its materials and images`);
  return { groups, problems };
}
