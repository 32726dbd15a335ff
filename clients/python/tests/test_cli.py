"""python3 -m cgview_client and examples/sdf_four_views.py against the real cgview-server."""
import os
import subprocess
import sys
import tempfile
import unittest

import harness
from cgview_client import png

server = None


def setUpModule():
    global server
    server = harness.start_module_server()


def run(*argv, script=None):
    """The program's exit status, standard output and standard error."""
    command = [sys.executable, script] if script else [sys.executable, "-m", "cgview_client"]
    env = {**os.environ, "CGVIEW_URL": server.url, "PYTHONPATH": harness.CLIENT_DIR}
    p = subprocess.run(command + list(argv), env=env, capture_output=True, text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


class CliTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="cgview-pyclient-cli-")
        self.addCleanup(lambda: subprocess.run(["rm", "-rf", self.dir]))

    def ok(self, *argv, script=None):
        status, out, err = run(*argv, script=script)
        self.assertEqual(status, 0, f"{argv}: {err}")
        return out.split("\n")[:-1], err

    def test_upload_list_run_wait_download(self):
        [mesh_id], _ = self.ok("upload", harness.ELEPHANT, "--name", "cli-elephant.off")
        lines, _ = self.ok("list")
        self.assertTrue(any(line.startswith(mesh_id) and "cli-elephant.off" in line for line in lines), lines)
        lines, err = self.ok("run", "centroid_distance", "cli-elephant.off", "-p", "exponent=0.5",
                             "-p", "normalize=true", "-o", self.dir)
        job_id, path = lines
        self.assertEqual(path, os.path.join(self.dir, "distance.json"))
        self.assertIn("100% done", err)  # the progress bar, on standard error
        self.ok("wait", job_id)
        [csv], _ = self.ok("download", job_id, "distance", "--format", "csv", "-o", self.dir)
        with open(csv) as f:
            self.assertEqual(len(f.read().strip().split("\n")), 2775 + 1)  # a header, then a row a vertex
        lines, _ = self.ok("list", "jobs")
        self.assertTrue(any(line.startswith(job_id) and "done" in line for line in lines), lines)

    def test_render_views(self):
        out = os.path.join(self.dir, "views.png")
        self.ok("render", harness.ELEPHANT, "--views", "3", "--size", "50x40", "-o", out)
        with open(out, "rb") as f:
            image = png.decode(f.read())
        self.assertEqual((image.width, image.height), (150, 40))

    def test_errors_are_one_line_and_a_failing_status(self):
        status, _, err = run("run", "centroid_distance", harness.ELEPHANT, "-p", "exponent=9")
        self.assertEqual(status, 1)
        self.assertEqual(err, "cgview_client: error: HTTP 400 bad_request: parameter 'exponent': 9 is over the maximum 4\n")
        status, _, err = run("run", "curvature", "no-such-mesh")
        self.assertEqual(status, 1)
        self.assertIn("no mesh with id or name 'no-such-mesh'", err)
        status, _, err = run("run", "curvature", harness.ELEPHANT, "-p", "oops")
        self.assertEqual((status, err), (1, "cgview_client: error: parameter 'oops' is not NAME=VALUE\n"))


class PaperFigureTest(unittest.TestCase):
    script = os.path.join(harness.CLIENT_DIR, "examples", "sdf_four_views.py")

    def test_four_views_of_a_field(self):
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "figure.png")
            status, stdout, err = run(harness.ELEPHANT, "--algorithm", "centroid_distance", "--artifact", "distance",
                                      "--size", "80x60", "-o", out, script=self.script)
            self.assertEqual(status, 0, err)
            self.assertEqual(stdout, out + "\n")
            with open(out, "rb") as f:
                figure = png.decode(f.read())
        self.assertEqual((figure.width, figure.height), (320, 60))
        self.assertGreater(harness.colourful(figure), 4 * 50)

    def test_an_artifact_the_job_does_not_give(self):
        status, _, err = run(harness.ELEPHANT, "--algorithm", "curvature", "--artifact", "sdf", script=self.script)
        self.assertEqual(status, 1)
        self.assertIn("curvature gave no artifact 'sdf' (it gave mean_curvature, gaussian_curvature)", err)


if __name__ == "__main__":
    unittest.main()
