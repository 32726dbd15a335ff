"""Meshes, fields, vector fields, grids and skeletons as numpy arrays, uploads from arrays,
Open3D and meshio meshes, checked parameters, the algorithms as methods and
many jobs at once, against the real server; the references are meshio's
reading of the sample file, numpy's own sums, and the artifacts' other formats."""
import os
import unittest

try:
    import numpy as np
except ImportError:
    np = None

import harness
from cgview_client import Client, ParameterError
from cgview_client import interop

try:
    import meshio
except ImportError:
    meshio = None
try:
    import open3d
except ImportError:
    open3d = None


class WithElephant(unittest.TestCase):
    """A server of its own, and elephant.off on it."""

    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server()
        cls.addClassCleanup(cls.server.stop)
        cls.client = Client(cls.server.url)
        cls.mesh = cls.client.upload(harness.ELEPHANT)


@unittest.skipIf(np is None, "numpy is not installed (Debian: python3-numpy)")
class ArraysTest(WithElephant):
    @unittest.skipIf(meshio is None, "meshio is not installed (Debian: python3-meshio)")
    def test_a_mesh_is_its_files_vertices_and_faces_in_order(self):
        ref = meshio.read(harness.ELEPHANT)
        self.assertEqual(self.mesh.vertices.dtype, np.float64)
        np.testing.assert_array_equal(self.mesh.vertices, ref.points)
        np.testing.assert_array_equal(self.mesh.faces, ref.cells_dict["triangle"])

    def test_arrays_upload_without_a_file_and_keep_every_digit(self):
        rng = np.random.default_rng(7)
        V = rng.normal(size=(50, 3)) * 1e3 + 1 / 3
        F = np.array([[i, i + 1, i + 2] for i in range(48)])
        m = self.client.upload_arrays(V, F, name="random")
        self.assertEqual(m["name"], "random.ply")
        self.assertEqual((m["report"]["vertices"], m["report"]["faces"]), (50, 48))
        np.testing.assert_array_equal(m.vertices, V)
        np.testing.assert_array_equal(m.faces, F)
        with self.assertRaises(ValueError):
            self.client.upload_arrays(V, [[0, 1, 50]])

    def test_a_field_is_an_array_in_the_meshs_vertex_order(self):
        job = self.client.run("centroid_distance", self.mesh, exponent=2.0)
        V = self.mesh.vertices
        expected = (np.linalg.norm(V - V.mean(axis=0), axis=1) ** 2).astype(np.float32)
        np.testing.assert_allclose(job.field(), expected, rtol=1e-5)
        self.assertEqual(job.field("distance").shape, (len(V),))

    def test_a_vector_field_is_an_n_by_3_array_with_its_location_and_hint(self):
        job = self.client.run("principal_directions", self.mesh)
        vf = job.vector_field()  # the first: max_direction
        self.assertEqual(vf.values.shape, (len(self.mesh.vertices), 3))
        self.assertEqual(vf.values.dtype, np.float32)
        self.assertEqual((vf.location, vf.hint), ("vertex", "direction"))
        finite = np.isfinite(vf.values).all(axis=1)
        self.assertGreater(finite.sum(), 0.9 * len(finite))
        # Principal directions: unit vectors where there is a value, at right angles to each other.
        np.testing.assert_allclose(np.linalg.norm(vf.values[finite], axis=1), 1, atol=1e-4)
        other = job.vector_field("min_direction").values
        both = finite & np.isfinite(other).all(axis=1)
        np.testing.assert_allclose(np.einsum("ij,ij->i", vf.values[both], other[both]), 0, atol=1e-3)
        self.assertAlmostEqual(vf.max_length, float(np.linalg.norm(vf.values[finite], axis=1).max()), places=5)
        # The same vectors in the json format (NaN written as null).
        import json
        rows = json.loads(self.client.artifact(job.id, "max_direction", "json")[0])["values"]
        np.testing.assert_array_equal(np.array([[np.nan if x is None else x for x in r] for r in rows], np.float32), vf.values)
        with self.assertRaisesRegex(ValueError, "is a scalar_field, not a vector_field"):
            job.vector_field("max_curvature")

    def test_a_voxel_grid_a_skeleton_and_metrics(self):
        job = self.client.run("voxelize", self.mesh, resolution=24)
        grid, m = job.grid(), job.metrics()  # the job's own measures as the reference
        self.assertEqual(grid.values.shape, (m["dim_x"], m["dim_y"], m["dim_z"]))
        self.assertEqual(grid.voxel_size, m["voxel_size"])
        self.assertEqual(int((grid.values > 0).sum()), m["occupied_voxels"])
        inside = grid.centers()[grid.values > 0]
        self.assertGreater(len(inside), 100)
        lo, hi = self.mesh.vertices.min(axis=0), self.mesh.vertices.max(axis=0)
        self.assertTrue((inside >= lo - grid.voxel_size).all() and (inside <= hi + grid.voxel_size).all())
        job = self.client.run("skeleton_mcf", self.mesh)
        s = job.skeleton()
        self.assertEqual(s.nodes.shape[1], 3)
        self.assertTrue(((s.edges >= 0) & (s.edges < len(s.nodes))).all())
        # The same skeleton in its OBJ form (v and l records), read here by hand.
        name = [a["name"] for a in job["artifacts"] if a["kind"] == "skeleton"][0]
        obj = self.client.artifact(job.id, name, "obj")[0].decode().split("\n")
        nodes = np.array([[float(x) for x in line.split()[1:4]] for line in obj if line.startswith("v ")])
        np.testing.assert_allclose(s.nodes, nodes, rtol=1e-6)
        metrics = self.client.run("skeleton_metrics", self.mesh, inputs={"skeleton": {"job": job.id, "artifact": name}}).metrics()
        self.assertIsInstance(metrics, dict)
        self.assertTrue(metrics)

    def test_a_job_without_a_mesh_input_and_a_chained_mesh(self):
        grid = self.client.run("voxelize", self.mesh, resolution=20)
        # grid_surface takes a voxel grid only: mesh None sends no 'mesh' input.
        surface = self.client.run("grid_surface", None, inputs={"grid": {"job": grid.id, "artifact": "grid"}})
        self.assertEqual(surface["inputs"].get("mesh"), None)
        self.assertEqual(surface.metrics()["voxels"], grid.metrics()["occupied_voxels"])
        # A {"job", "artifact"} mesh chains an earlier job's mesh as the input 'mesh'.
        distance = self.client.run("centroid_distance", {"job": surface.id, "artifact": "mesh"})
        self.assertEqual(distance.field().shape, (len(surface.mesh()[0]),))

    def test_a_point_cloud_comes_back_as_arrays(self):
        # A sphere's points as XYZ; estimate_normals gives each its normal,
        # the position itself up to sign (PCA of its neighbours: the plane).
        n = 400
        i = np.arange(n) + 0.5
        z = 1 - 2 * i / n
        r = np.sqrt(1 - z * z)
        phi = np.pi * (1 + 5 ** 0.5) * i
        sphere = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
        text = "".join(f"{x!r} {y!r} {w!r}\n" for x, y, w in sphere)
        cloud = self.client.upload_bytes(text.encode(), "sphere.xyz")
        self.assertTrue(cloud["points"])
        job = self.client.run("estimate_normals", None, inputs={"points": cloud.id})
        pc = job.points()
        np.testing.assert_allclose(pc.positions, sphere, atol=1e-6)  # float32, as stored
        self.assertEqual(pc.normals.shape, (n, 3))
        self.assertGreater(np.abs((pc.normals * sphere).sum(axis=1)).min(), 0.9)
        self.assertIsNone(pc.colors)
        # Open3D reads the same points from the artifact's ply.
        if open3d is not None:
            import tempfile
            with tempfile.TemporaryDirectory() as d:
                path = os.path.join(d, "points.ply")
                with open(path, "wb") as f:
                    f.write(self.client.artifact(job.id, "points", "ply")[0])
                o3d = open3d.io.read_point_cloud(path)
            np.testing.assert_array_equal(np.asarray(o3d.points), pc.positions)
            np.testing.assert_allclose(np.asarray(o3d.normals), pc.normals, atol=1e-6)
        with self.assertRaisesRegex(ValueError, "is a points, not a mesh"):
            job.mesh("points")

    @unittest.skipIf(open3d is None, "open3d is not installed (Debian: python3-open3d)")
    def test_open3d_meshes_both_ways(self):
        box = open3d.geometry.TriangleMesh.create_box(2.0, 1.0, 0.5)
        m = self.client.upload_open3d(box, name="box.ply")
        np.testing.assert_array_equal(m.vertices, np.asarray(box.vertices))
        back = m.to_open3d()
        np.testing.assert_array_equal(np.asarray(back.triangles), np.asarray(box.triangles))
        self.assertAlmostEqual(back.get_surface_area(), box.get_surface_area())

    @unittest.skipIf(meshio is None, "meshio is not installed (Debian: python3-meshio)")
    def test_meshio_meshes_both_ways(self):
        ref = meshio.read(harness.ELEPHANT)
        m = self.client.upload_meshio(ref, name="elephant-from-meshio")
        out = m.to_meshio()
        np.testing.assert_array_equal(out.points, ref.points)
        np.testing.assert_array_equal(out.cells_dict["triangle"], ref.cells_dict["triangle"])
        quad = meshio.Mesh(np.zeros((4, 3)), [("quad", np.array([[0, 1, 2, 3]]))])
        with self.assertRaises(ValueError) as caught:
            interop.from_meshio(quad)
        self.assertIn("quad", str(caught.exception))


class ParametersTest(WithElephant):
    """Needs no numpy."""

    def test_a_misspelt_or_out_of_range_parameter_raises_before_anything_is_sent(self):
        before = len(self.client.jobs())
        with self.assertRaises(ParameterError) as caught:
            self.client.submit("sdf", self.mesh, rayz=25)
        self.assertEqual(str(caught.exception), "HTTP 400 bad_request: algorithm 'sdf' has no parameter 'rayz' (did you mean 'rays'?)")
        self.assertEqual(caught.exception.parameter, "rayz")
        with self.assertRaises(ParameterError) as caught:
            self.client.submit("centroid_distance", self.mesh, exponent=9)
        self.assertEqual(len(self.client.jobs()), before, "a refused job was sent")
        # The words are the server's own for the same request.
        body = {"algorithm": "centroid_distance", "inputs": {"mesh": self.mesh.id}, "params": {"exponent": 9}}
        with self.assertRaises(Exception) as server:
            self.client.send_json("POST", "/jobs", body)
        self.assertEqual(str(caught.exception), str(server.exception))

    def test_every_algorithm_is_a_documented_method(self):
        doc = self.client.algorithms.centroid_distance.__doc__
        self.assertIn("exponent (number, 0.1..4, default 1.0)", doc)
        self.assertIn("raise each distance to this power", doc)
        self.assertIn("sdf", dir(self.client.algorithms))
        job = self.client.algorithms.centroid_distance(self.mesh, exponent=3.0)
        self.assertEqual((job["state"], job["params"]["exponent"]), ("done", 3.0))
        with self.assertRaises(AttributeError) as caught:
            self.client.algorithms.sfd
        self.assertIn("did you mean 'sdf'", str(caught.exception))
        self.assertIsInstance(self.client.algorithms(), list)

    def test_map_runs_one_job_per_mesh_in_order(self):
        other = self.client.upload(os.path.join(harness.SAMPLES, "sphere.off"))
        jobs = self.client.map("centroid_distance", [self.mesh, other.id], exponent=0.5)
        self.assertEqual([j["inputs"]["mesh"] for j in jobs], [self.mesh.id, other.id])
        self.assertEqual({j["state"] for j in jobs}, {"done"})


if __name__ == "__main__":
    unittest.main()
