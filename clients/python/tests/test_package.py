"""The client as a package: `pip install ./clients/python` into a venv made
with Debian's python3 (no package index: the build backend is the standard
library, _build/backend.py), its command, and the standard-library path
without numpy.  Venvs of other Pythons (pyenv's): tests/pip_install.py."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import harness

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable


def venv(directory, system_site_packages):
    args = [PYTHON, "-m", "venv", directory] + (["--system-site-packages"] if system_site_packages else [])
    subprocess.run(args, check=True, capture_output=True)
    return os.path.join(directory, "bin")


@unittest.skipIf(subprocess.run([PYTHON, "-c", "import venv, ensurepip"], capture_output=True).returncode != 0,
                 "python3-venv is not installed")
class PackageTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="cgview-pypkg-")
        cls.addClassCleanup(shutil.rmtree, cls.dir, True)
        # A copy, so that the build leaves nothing in the source tree.
        cls.source = os.path.join(cls.dir, "src")
        shutil.copytree(harness.CLIENT_DIR, cls.source, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
        cls.server = harness.Server()
        cls.addClassCleanup(cls.server.stop)

    def install(self, name, system_site_packages):
        bin_dir = venv(os.path.join(self.dir, name), system_site_packages)
        env = {**os.environ, "PIP_NO_INDEX": "1", "PIP_DISABLE_PIP_VERSION_CHECK": "1"}
        p = subprocess.run([os.path.join(bin_dir, "pip"), "install", self.source], capture_output=True, text=True, env=env)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        return bin_dir

    def run_in(self, bin_dir, code):
        p = subprocess.run([os.path.join(bin_dir, "python"), "-c", code], capture_output=True, text=True, cwd=self.dir,
                           env={**os.environ, "CGVIEW_URL": self.server.url, "PYTHONPATH": ""})
        return p.returncode, p.stdout + p.stderr

    def test_pip_installs_it_beside_debians_numpy(self):
        bin_dir = self.install("with-numpy", True)
        rc, out = self.run_in(bin_dir, "import cgview_client, numpy\n"
                                       f"c = cgview_client.Client()\nm = c.upload({harness.ELEPHANT!r})\n"
                                       "print(cgview_client.__file__, m.vertices.shape, m.faces.dtype)")
        self.assertEqual(rc, 0, out)
        self.assertIn(os.path.join(self.dir, "with-numpy"), out)
        self.assertIn("(2775, 3) int64", out)
        p = subprocess.run([os.path.join(bin_dir, "cgview-client"), "health", "--url", self.server.url],
                           capture_output=True, text=True)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertIn('"status": "ok"', p.stdout)

    def test_without_numpy_the_standard_library_client_works(self):
        bin_dir = self.install("no-numpy", False)
        rc, out = self.run_in(bin_dir, "import importlib.util, cgview_client\n"
                                       "assert importlib.util.find_spec('numpy') is None, 'numpy is there'\n"
                                       f"c = cgview_client.Client()\nm = c.upload({harness.ELEPHANT!r})\n"
                                       "print(c.run('centroid_distance', m, exponent=2.0)['state'])\n"
                                       "try:\n    m.vertices\nexcept ImportError as e:\n    print(e)\n")
        self.assertEqual(rc, 0, out)
        self.assertIn("done", out)
        self.assertIn("arrays need numpy (Debian: apt install python3-numpy)", out)


if __name__ == "__main__":
    unittest.main()
