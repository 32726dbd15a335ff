"""Meshes to and from Open3D and meshio (each imported when used)."""
from . import arrays


def to_open3d(V, F):
    import open3d as o3d
    np = arrays.numpy()
    return o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(np.asarray(V, dtype=np.float64)),
                                     o3d.utility.Vector3iVector(np.asarray(F, dtype=np.int32)))


def from_open3d(mesh):
    """(V, F) of an open3d.geometry.TriangleMesh."""
    np = arrays.numpy()
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.triangles, dtype=np.int64)


def to_meshio(V, F):
    import meshio
    return meshio.Mesh(arrays.numpy().asarray(V, dtype="f8"), [("triangle", arrays.numpy().asarray(F))])


def from_meshio(mesh):
    """(V, F) of a meshio.Mesh's triangles (other cells are refused, naming them)."""
    np = arrays.numpy()
    kinds = [c.type for c in mesh.cells]
    if any(k != "triangle" for k in kinds):
        raise ValueError(f"only triangles are uploaded; the mesh has {sorted(set(kinds))} cells")
    F = np.concatenate([c.data for c in mesh.cells]) if mesh.cells else np.zeros((0, 3), dtype=np.int64)
    return np.asarray(mesh.points, dtype=np.float64)[:, :3], F.astype(np.int64)
