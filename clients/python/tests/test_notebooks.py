"""The paper's figures as notebooks (clients/python/notebooks), executed
headless by nbclient in an IPython kernel against the real server, and the
HTML progress bar that job waiting shows in a notebook.

The pictures go to $CGVIEW_FIGURES_DIR when it is set (they stay there to be
looked at), else to a temporary folder removed afterwards."""
import asyncio
import glob
import os
import shutil
import struct
import tempfile
import time
import unittest
from unittest import mock

import harness

try:
    import nbclient
    import nbformat
    import ipykernel  # noqa: F401 (the kernel nbclient starts)
except ImportError as e:
    nbclient = None
    MISSING = f"notebooks need Debian's python3-nbclient and python3-ipykernel: {e}"

NOTEBOOKS = os.path.join(harness.CLIENT_DIR, "notebooks")
# Each notebook and the pictures it must write.
FIGURES = {
    "figure01-03_voxelization.ipynb": ["figure01_resolutions.png", "figure02_section.png", "figure03_slices.png"],
    "figure05_skeletons.ipynb": ["figure05_skeletons.png"],
    "figure08_vote_grid.ipynb": ["figure08_thresholds.png"],
    "figure09_sdf.ipynb": ["figure09_sdf.png"],
    "figure10_segmentation.ipynb": ["figure10_segmentation.png"],
    "figure11_ikeda.ipynb": ["figure11_ikeda.png"],
}
CELL_TIMEOUT = 300  # seconds for one cell: the slowest takes a few on 2 busy cores

server = None
figures_dir = None
timings = {}


def setUpModule():
    global server, figures_dir
    if nbclient is None:
        raise unittest.SkipTest(MISSING)
    server = harness.start_module_server()
    figures_dir = os.environ.get("CGVIEW_FIGURES_DIR")
    if not figures_dir:
        figures_dir = tempfile.mkdtemp(prefix="cgview-figures-")
        unittest.addModuleCleanup(shutil.rmtree, figures_dir, ignore_errors=True)


def tearDownModule():
    if timings:
        print("\nnotebook run times: " + ", ".join(f"{name} {seconds:.1f} s" for name, seconds in timings.items()))


if nbclient is not None:
    class RecordingClient(nbclient.NotebookClient):
        """nbclient's client, counting the progress bar's in-place updates
        (update_display_data), which it applies to the outputs and drops."""

        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            self.progress_updates = 0

        def process_message(self, msg, cell, cell_index):
            if msg["msg_type"] == "update_display_data" and \
                    "cgview-progress" in msg["content"].get("data", {}).get("text/html", ""):
                self.progress_updates += 1
            return super().process_message(msg, cell, cell_index)


def execute(notebook, path=NOTEBOOKS):
    """Runs a notebook (nbformat node) in a fresh python3 kernel whose
    environment names the test's server; the executed notebook and the client
    (CellExecutionError, with the cell's traceback, when a cell fails)."""
    scratch = tempfile.mkdtemp(prefix="cgview-kernel-")
    try:
        environment = {
            "CGVIEW_URL": server.url,
            "CGVIEW_SAMPLES": harness.SAMPLES,
            "CGVIEW_FIGURES_DIR": figures_dir,
            # The kernel imports this checkout's cgview_client, not an installed one.
            "PYTHONPATH": os.pathsep.join(p for p in (harness.CLIENT_DIR, os.environ.get("PYTHONPATH")) if p),
            "MPLBACKEND": "Agg",
            "PYTHONDONTWRITEBYTECODE": "1",
            # ipykernel's debugger otherwise warns on stderr about frozen modules.
            "PYDEVD_DISABLE_FILE_VALIDATION": "1",
            # Connection files and IPython's profile in a scratch folder, not the home's.
            "JUPYTER_RUNTIME_DIR": scratch,
            "IPYTHONDIR": scratch,
        }
        with mock.patch.dict(os.environ, environment):
            for name in ("CGVIEW_TOKEN", "CGVIEW_CA_FILE"):  # the test's server needs neither
                os.environ.pop(name, None)
            client = RecordingClient(notebook, kernel_name="python3", timeout=CELL_TIMEOUT,
                                     resources={"metadata": {"path": path}})
            # asyncio.run closes its loop: nbclient's execute() leaves one open.
            asyncio.run(client.async_execute())
        return notebook, client
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def progress_outputs(cell):
    """The HTML progress bars among a code cell's outputs."""
    return [o for o in cell.get("outputs", []) if o.get("output_type") == "display_data"
            and "cgview-progress" in o.get("data", {}).get("text/html", "")]


def png_size(path):
    """(width, height) from a PNG's header; ValueError when it is not one."""
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise ValueError(f"{path} is not a PNG")
    return struct.unpack(">II", head[16:24])


class FigureNotebooksTest(unittest.TestCase):
    def test_every_notebook_is_tested(self):
        found = sorted(os.path.basename(p) for p in glob.glob(os.path.join(NOTEBOOKS, "*.ipynb")))
        self.assertEqual(found, sorted(FIGURES))

    def test_notebooks_are_kept_without_outputs(self):
        for name in FIGURES:
            notebook = nbformat.read(os.path.join(NOTEBOOKS, name), as_version=4)
            nbformat.validate(notebook)
            for cell in notebook.cells:
                if cell.cell_type == "code":
                    self.assertEqual((cell.outputs, cell.execution_count), ([], None), name)

    def check_notebook(self, name):
        notebook = nbformat.read(os.path.join(NOTEBOOKS, name), as_version=4)
        started = time.monotonic()
        notebook, client = execute(notebook)
        timings[name] = time.monotonic() - started
        for picture in FIGURES[name]:
            path = os.path.join(figures_dir, picture)
            self.assertTrue(os.path.isfile(path), f"{name} did not write {path}")
            width, height = png_size(path)
            self.assertGreaterEqual(min(width, height), 250, path)
            self.assertGreater(os.path.getsize(path), 20_000, f"{path} is too small to show a figure")
            self.assertGreater(self.ink(path), 0.02, f"{path} is almost blank")
        # Every job waited for showed one bar, left at 100% done by its updates.
        bars = [o for cell in notebook.cells if cell.cell_type == "code" for o in progress_outputs(cell)]
        self.assertTrue(bars, f"{name} showed no progress bar")
        for bar in bars:
            self.assertIn("100%", bar["data"]["text/html"], name)
            self.assertTrue(bar["data"]["text/plain"].endswith("100% done"), bar["data"]["text/plain"])

    @staticmethod
    def ink(path):
        """The share of a picture's pixels that are not white."""
        import matplotlib.image
        image = matplotlib.image.imread(path)
        return float((image[..., :3].min(axis=2) < 0.95).mean())


def add_notebook_tests():
    # One test per notebook: a failure names the notebook, and the others still run.
    for name in FIGURES:
        method = "test_" + os.path.splitext(name)[0].replace("-", "_")
        def test(self, name=name):
            self.check_notebook(name)
        test.__doc__ = f"{name} runs and writes {', '.join(FIGURES[name])}"
        setattr(FigureNotebooksTest, method, test)


add_notebook_tests()


class NotebookProgressBarTest(unittest.TestCase):
    """In a kernel, run, result and map show one HTML bar per call, updated in
    place; on_progress=False shows none."""

    def test_bars_in_a_kernel(self):
        cell = nbformat.v4.new_code_cell
        notebook = nbformat.v4.new_notebook(cells=[
            cell("from cgview_client import Client\n"
                 "c = Client()\n"
                 f"mesh = c.upload({harness.ELEPHANT!r})\n"
                 f"other = c.upload_arrays(mesh.vertices * 2, mesh.faces, name='bigger')"),
            cell("job = c.run('sdf', mesh, rays=24)"),
            cell("jobs = c.map('centroid_distance', [mesh, other], exponent=1.25)\n"
                 "assert [j['state'] for j in jobs] == ['done', 'done']"),
            cell("c.submit('centroid_distance', mesh, exponent=1.75).result()"),
            cell("quiet = c.run('centroid_distance', mesh, exponent=2.25, on_progress=False)"),
            cell("from cgview_client.progress import in_notebook\nassert in_notebook()"),
        ])
        notebook, client = execute(notebook, tempfile.gettempdir())
        setup, run, mapped, result, quiet, _ = notebook.cells
        self.assertEqual(progress_outputs(setup), [])
        [bar] = progress_outputs(run)
        self.assertEqual(bar["data"]["text/plain"], "sdf 100% done")
        self.assertIn('width:100.0%', bar["data"]["text/html"])
        [bar] = progress_outputs(mapped)  # one bar for both jobs
        self.assertEqual(bar["data"]["text/plain"], "centroid_distance 2/2 100% done")
        [bar] = progress_outputs(result)
        self.assertEqual(bar["data"]["text/plain"], "centroid_distance 100% done")
        self.assertEqual(progress_outputs(quiet), [])
        # The bars moved: the kernel sent updates that replaced the first pictures.
        self.assertGreater(client.progress_updates, 0)


if __name__ == "__main__":
    unittest.main()
