"""CGView's stored data as numpy arrays, and arrays as uploads: numpy is
imported here only, when one of these is called (the rest of the client
needs the standard library alone)."""
import json
import struct
from dataclasses import dataclass


def numpy():
    try:
        import numpy as np
    except ImportError as e:
        raise ImportError("arrays need numpy (Debian: apt install python3-numpy)") from e
    return np


def off_arrays(data):
    """(V float64 (n, 3), F int64 (m, 3)) of an OFF file's bytes, as the server
    writes them (its download in format "off": every digit of each position,
    vertices in the stored order; triangles)."""
    np = numpy()
    words = data.split()
    start = 1 if words and words[0] in (b"OFF", b"COFF") else 0
    n, m = int(words[start]), int(words[start + 1])
    first = start + 3
    per_vertex = 3 if words[0] == b"OFF" else 7  # COFF: x y z r g b a
    V = np.array(words[first:first + n * per_vertex], dtype=np.float64).reshape(n, per_vertex)[:, :3].copy()
    faces = np.array(words[first + n * per_vertex:first + n * per_vertex + m * 4], dtype=np.int64).reshape(m, 4)
    if m and (faces[:, 0] != 3).any():
        raise ValueError("the OFF file has faces that are not triangles")
    return V, faces[:, 1:].copy()


def ply_bytes(V, F):
    """A binary PLY of vertices (float64) and triangles (int32): what
    upload_arrays sends, every digit of the positions kept."""
    np = numpy()
    V = np.ascontiguousarray(V, dtype="<f8")
    F = np.asarray(F)
    if V.ndim != 2 or V.shape[1] != 3:
        raise ValueError(f"vertices must be an (n, 3) array, not {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError(f"faces must be an (m, 3) array of vertex indices, not {F.shape}")
    if F.size and (F.min() < 0 or F.max() >= len(V)):
        raise ValueError(f"a face index is outside 0..{len(V) - 1}")
    faces = np.empty(len(F), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = F
    header = (f"ply\nformat binary_little_endian 1.0\ncomment from cgview_client.upload_arrays\n"
              f"element vertex {len(V)}\nproperty double x\nproperty double y\nproperty double z\n"
              f"element face {len(F)}\nproperty list uchar int vertex_indices\nend_header\n")
    return header.encode() + V.tobytes() + faces.tobytes()


def field_array(data):
    """A scalar field's values (its "f32" format) as float32, in the order of
    the mesh's own vertices or faces."""
    return numpy().frombuffer(data, dtype="<f4").copy()


@dataclass
class VectorField:
    """values (n, 3) float32: a vector per vertex or per face of the mesh, in
    its stored order, a row of NaN where there is none; location "vertex" or
    "face"; hint "direction" (unit vectors whose sign means nothing) or
    "arrow" (length and sign mean something); max_length: the longest finite
    vector's length."""
    values: object
    location: str
    hint: str
    max_length: float = None


def vector_array(data):
    """A vector field's vectors (its "f32" format: x, y, z float32 triples) as
    an (n, 3) float32 array."""
    if len(data) % 12:
        raise ValueError(f"{len(data)} bytes are not whole float32 x, y, z triples")
    return numpy().frombuffer(data, dtype="<f4").reshape(-1, 3).astype("float32")


@dataclass
class PointCloud:
    """positions (n, 3) float64 (stored as float32), normals (n, 3) float32 or
    None, colors (n, 4) uint8 RGBA or None: a point cloud artifact, its
    points in the order the algorithm gave them."""
    positions: object
    normals: object = None
    colors: object = None


_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "<i2", "int16": "<i2",
              "ushort": "<u2", "uint16": "<u2", "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
              "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8"}


def ply_points(data):
    """A PointCloud from a binary little-endian PLY whose first element is
    its vertices (the server's "ply" of a points artifact; Open3D's and
    CloudCompare's PLY of a cloud too)."""
    np = numpy()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply") or end < 0:
        raise ValueError("not a PLY file")
    header = data[:end].decode("ascii", "replace").splitlines()
    if "format binary_little_endian 1.0" not in header:
        raise ValueError("the PLY is not binary little-endian")
    count, fields, element = None, [], None
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            element = words[1]
            if element == "vertex":
                count = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            if words[1] == "list" or words[1] not in _PLY_TYPES:
                raise ValueError(f"vertex property '{line}' is not a number")
            fields.append((words[2], _PLY_TYPES[words[1]]))
    if count is None:
        raise ValueError("the PLY has no vertex element")
    rows = np.frombuffer(data, dtype=np.dtype(fields), count=count, offset=end + len("end_header\n"))
    names = set(rows.dtype.names)

    def columns(*keys, dtype):
        return np.stack([rows[k] for k in keys], axis=1).astype(dtype) if names.issuperset(keys) else None

    colors = columns("red", "green", "blue", dtype="uint8")
    if colors is not None:
        alpha = rows["alpha"] if "alpha" in names else np.full(count, 255)
        colors = np.concatenate([colors, alpha.astype("uint8")[:, None]], axis=1)
    return PointCloud(columns("x", "y", "z", dtype="float64"), columns("nx", "ny", "nz", dtype="float32"), colors)


@dataclass
class VoxelGrid:
    """values[x, y, z] (uint8 occupancy, or float32), the grid's corner
    (`origin`, the low corner of voxel 0) and its voxel size."""
    values: object
    origin: tuple
    voxel_size: float
    kind: str  # bit, uint8 or float32, as CGView stores it

    def centers(self):
        """The centre of each voxel, an array of shape values.shape + (3,)."""
        np = numpy()
        axes = [self.origin[a] + (np.arange(self.values.shape[a]) + 0.5) * self.voxel_size for a in range(3)]
        return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1)


def nrrd_grid(data):
    """A VoxelGrid from the NRRD the server writes (raw, little-endian, one
    sample per voxel centre, x fastest)."""
    np = numpy()
    end = data.find(b"\n\n")
    if not data.startswith(b"NRRD") or end < 0:
        raise ValueError("not a NRRD file")
    fields = {}
    for line in data[:end].decode().splitlines()[1:]:
        if line.startswith("#") or not line.strip():
            continue
        key, sep, value = line.partition(": ") if ": " in line else line.partition(":=")
        fields[key.strip()] = value.strip()
    if fields.get("encoding", "raw") != "raw":
        raise ValueError(f"NRRD encoding {fields['encoding']} is not read here")
    sizes = [int(s) for s in fields["sizes"].split()]
    numbers = lambda text: [float(x) for x in text.replace("(", " ").replace(")", " ").replace(",", " ").split()]
    step = numbers(fields["space directions"])[0]
    centre = numbers(fields["space origin"])
    dtype = {"float": "<f4", "uint8": "u1", "uchar": "u1"}[fields["type"]]
    flat = np.frombuffer(data, dtype=dtype, count=sizes[0] * sizes[1] * sizes[2], offset=end + 2)
    values = flat.reshape(sizes[2], sizes[1], sizes[0]).transpose(2, 1, 0).copy()
    origin = tuple(c - 0.5 * step for c in centre)
    return VoxelGrid(values, origin, step, fields.get("cgview_type", "float32" if dtype == "<f4" else "uint8"))


@dataclass
class Skeleton:
    """nodes (n, 3) float64, edges (k, 2) int64 node indices, radii (n,) or None."""
    nodes: object
    edges: object
    radii: object = None


def skeleton_arrays(data):
    """A Skeleton from the server's skeleton JSON ({"nodes", "edges", "radii"?})."""
    np = numpy()
    j = json.loads(data)
    nodes = np.array(j["nodes"], dtype=np.float64).reshape(-1, 3)
    edges = np.array(j.get("edges", []), dtype=np.int64).reshape(-1, 2)
    radii = np.array(j["radii"], dtype=np.float64) if "radii" in j else None
    return Skeleton(nodes, edges, radii)
