"""A mesh and a job as the server answers them (the same dicts as before,
so m["id"] keeps working), with their data as arrays and a job that can be
waited for."""
from . import arrays


class Mesh(dict):
    """A stored mesh: its JSON fields, and .vertices (n, 3) float64 and
    .faces (m, 3) int64 in the server's stored order (downloaded once)."""

    def __init__(self, client, fields):
        super().__init__(fields)
        self._client = client
        self._arrays = None

    @property
    def id(self):
        return self["id"]

    def arrays(self):
        """(vertices, faces), downloaded once."""
        if self._arrays is None:
            self._arrays = arrays.off_arrays(self._client.download_mesh(self.id, "off"))
        return self._arrays

    @property
    def vertices(self):
        return self.arrays()[0]

    @property
    def faces(self):
        return self.arrays()[1]

    def to_open3d(self):
        """An open3d.geometry.TriangleMesh (Debian: python3-open3d)."""
        from . import interop
        return interop.to_open3d(*self.arrays())

    def to_meshio(self):
        """A meshio.Mesh of triangles (Debian: python3-meshio)."""
        from . import interop
        return interop.to_meshio(*self.arrays())

    def show(self, field=None, mode=None, width=800, height=500):
        """In a notebook, the viewer on this mesh in the output cell, over the
        server's picture of it (which is what an exported notebook shows);
        field: a scalar field to colour it by ("JOB_ID/NAME", "NAME" or a
        Job); mode: points, wireframe, flat, smooth or toon.  A
        notebook.View (its .url(), .png())."""
        from . import notebook
        return notebook.mesh_view(self._client, self, field, mode, width, height)


class Job(dict):
    """A job: its JSON fields (refreshed by wait/result), and its artifacts
    as arrays."""

    def __init__(self, client, fields):
        super().__init__(fields)
        self._client = client

    @property
    def id(self):
        return self["id"]

    def refresh(self):
        self.update(self._client.job(self.id))
        return self

    def result(self, timeout=None, on_progress=None):
        """Waits for the job to end: itself when done, else JobFailed.  Ctrl-C
        (KeyboardInterrupt) cancels the job before it goes on up.  In a
        notebook an HTML progress bar shows unless on_progress says otherwise
        (a callable, or False for none)."""
        from .errors import JobFailed
        from .progress import default_progress
        try:
            self.update(self._client.wait(self.id, default_progress(on_progress), timeout))
        except KeyboardInterrupt:
            self._client.cancel(self.id)
            raise
        if self["state"] != "done":
            raise JobFailed(dict(self))
        return self

    def cancel(self):
        self.update(self._client.cancel(self.id))
        return self

    def show(self, artifact=None, mode=None, width=800, height=500):
        """In a notebook, the viewer on this done job's mesh coloured by its
        scalar field (the first, or `artifact`), over the server's picture
        of it; a job without one shows its input mesh.  A notebook.View."""
        from . import notebook
        return notebook.job_view(self._client, self, artifact, mode, width, height)

    def _artifact(self, name, kind):
        for a in self.get("artifacts", []):
            if name is None and a["kind"] == kind or a["name"] == name:
                if a["kind"] != kind:
                    raise ValueError(f"artifact '{a['name']}' of job {self.id} is a {a['kind']}, not a {kind}")
                return a["name"]
        names = [a["name"] for a in self.get("artifacts", [])]
        raise KeyError(f"job {self.id} has no {kind} artifact{' ' + repr(name) if name else ''} (it has {names})")

    def field(self, name=None):
        """A scalar field artifact (the first, or the one named) as a float32
        array in the order of the input mesh's vertices or faces."""
        name = self._artifact(name, "scalar_field")
        return arrays.field_array(self._client.artifact(self.id, name, "f32")[0])

    def vector_field(self, name=None):
        """A vector field artifact (the first, or the one named) as
        arrays.VectorField: .values (n, 3) float32 in the order of the input
        mesh's vertices or faces (NaN rows: no value), .location, .hint
        ("direction" or "arrow") and .max_length."""
        name = self._artifact(name, "vector_field")
        entry = next(a for a in self["artifacts"] if a["name"] == name)
        values = arrays.vector_array(self._client.artifact(self.id, name, "f32")[0])
        return arrays.VectorField(values, entry.get("location", "vertex"), entry.get("hint", "arrow"),
                                  entry.get("max_length"))

    def grid(self, name=None):
        """A voxel grid artifact as arrays.VoxelGrid (values[x, y, z], origin, voxel_size)."""
        name = self._artifact(name, "voxel_grid")
        return arrays.nrrd_grid(self._client.artifact(self.id, name, "nrrd")[0])

    def skeleton(self, name=None):
        """A skeleton artifact as arrays.Skeleton (nodes, edges, radii)."""
        name = self._artifact(name, "skeleton")
        return arrays.skeleton_arrays(self._client.artifact(self.id, name, "json")[0])

    def metrics(self, name=None):
        """A metrics artifact as a dict."""
        import json
        name = self._artifact(name, "metrics")
        return json.loads(self._client.artifact(self.id, name, "json")[0])

    def points(self, name=None):
        """A point cloud artifact as arrays.PointCloud (positions, and normals
        and colors where it has them)."""
        name = self._artifact(name, "points")
        return arrays.ply_points(self._client.artifact(self.id, name, "ply")[0])

    def mesh(self, name=None):
        """A mesh artifact as (vertices, faces) arrays."""
        name = self._artifact(name, "mesh")
        return arrays.off_arrays(self._client.artifact(self.id, name, "off")[0])
