// Which files the upload control sends to POST /data (protocol/API.md) rather
// than to POST /meshes, and as what. The server takes the kind from the
// name's extension too, but .ply, .obj and .json are meshes as well as fields
// or skeletons: those stay mesh uploads here (what the control always did),
// and "Load skeleton file…" and "Load field file…" name the kind instead.
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
