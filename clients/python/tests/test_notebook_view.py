"""mesh.show() and job.show() in a notebook (cgview_client/notebook.py),
against the real server: notebooks executed headless by nbclient show the
viewer's iframe on the view link of that mesh and field over the server's
picture of it; the link is the viewer's own encoding (web-client's
view_state.ts re-encodes it byte for byte); off loopback the page gets a
sign-in ticket, good once, and no output or URL holds the token.

The browser's side (the iframe signs in with the ticket and draws the mesh)
is web-client/tests/notebook_view.e2e.test.mjs."""
import asyncio
import base64
import json
import os
import re
import shutil
import subprocess
import tempfile
import time
import unittest
import urllib.error
import urllib.request
from html.parser import HTMLParser
from unittest import mock

import harness
from cgview_client import CGViewError, Client, png
from cgview_client.notebook import View, camera, decode_view_hash, js_json, view_hash

try:
    import nbclient
    import nbformat
    import ipykernel  # noqa: F401 (the kernel nbclient starts)
except ImportError as e:
    nbclient = None
    MISSING = f"notebooks need Debian's python3-nbclient and python3-ipykernel: {e}"

WEB_CLIENT = os.path.join(harness.REPO, "web-client")


class Frames(HTMLParser):
    """The iframes' src and the images' src of an output's HTML."""

    def __init__(self, page):
        super().__init__()
        self.iframes, self.images, self.links = [], [], []
        self.feed(page)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        {"iframe": self.iframes, "img": self.images, "a": self.links}.get(tag, []).append(a.get("src") or a.get("href"))


def run_cells(sources, environment):
    """Runs code cells in a fresh python3 kernel with `environment` added:
    the executed notebook (CellExecutionError when a cell fails)."""
    notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(s) for s in sources])
    scratch = tempfile.mkdtemp(prefix="cgview-kernel-")
    try:
        env = {"PYTHONPATH": os.pathsep.join(p for p in (harness.CLIENT_DIR, os.environ.get("PYTHONPATH")) if p),
               "PYTHONDONTWRITEBYTECODE": "1", "PYDEVD_DISABLE_FILE_VALIDATION": "1",
               "JUPYTER_RUNTIME_DIR": scratch, "IPYTHONDIR": scratch, **environment}
        with mock.patch.dict(os.environ, env):
            for name in ("CGVIEW_TOKEN", "CGVIEW_CA_FILE", "CGVIEW_VIEW_URL"):
                if name not in environment:
                    os.environ.pop(name, None)
            client = nbclient.NotebookClient(notebook, kernel_name="python3", timeout=300,
                                             resources={"metadata": {"path": scratch}})
            asyncio.run(client.async_execute())
        return notebook
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def view_output(cell):
    """The one display of a View among a cell's outputs (its data: text/html, image/png, text/plain)."""
    outputs = [o for o in cell.outputs if o.get("output_type") in ("execute_result", "display_data")
               and "cgview-view" in o.get("data", {}).get("text/html", "")]
    assert len(outputs) == 1, cell.outputs
    return outputs[0]["data"]


def fragment(url):
    return url.split("#", 1)[1]


def post(server_url, path, body, token=None):
    """(status, JSON) of a POST, without the client (a page has no token)."""
    request = urllib.request.Request(server_url + "/api/v1" + path, data=json.dumps(body).encode(), method="POST",
                                     headers={"Content-Type": "application/json",
                                              **({"Authorization": f"Bearer {token}"} if token else {})})
    try:
        with urllib.request.urlopen(request, timeout=30) as r:
            return r.status, json.load(r)
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"null")


class ViewLinkEncodingTest(unittest.TestCase):
    """The hash is the viewer's: JSON.stringify's text, base64url without padding."""

    def test_numbers_and_text_as_javascript_writes_them(self):
        self.assertEqual(js_json({"a": [2.0, 0.1, 1e-7, 1e21, -0.0, 123.5], "b": "é\n\"", "c": None, "d": True}),
                         '{"a":[2,0.1,1e-7,1e+21,0,123.5],"b":"é\\n\\"","c":null,"d":true}')

    def test_the_camera_looks_at_the_box_from_the_pictures_side(self):
        c = camera({"min": [-1, -1, -1], "max": [1, 1, 1]})
        self.assertEqual(c["target"], [0, 0, 0])
        self.assertEqual(c["up"], [0, 1, 0])
        x, y, z = c["position"]
        self.assertGreater(x, 0)
        self.assertGreater(y, 0)
        self.assertGreater(z, x)  # azimuth 30: more in front than to the side
        self.assertAlmostEqual((x * x + y * y + z * z) ** 0.5, 3 ** 0.5 / 0.3420201433256687 * 1.05)

    def test_the_viewer_reads_and_writes_the_same_hash(self):
        """view_state.ts (loaded in node as the web client's unit tests load
        it) decodes the Python hash and encodes it back byte for byte."""
        if not shutil.which("node") or not os.path.isdir(os.path.join(WEB_CLIENT, "node_modules", "typescript")):
            self.skipTest("needs node and web-client/node_modules (npm ci in web-client)")
        state = {"v": 1, "mesh": "9f2c1a7e5b3d4c21",
                 "camera": camera({"min": [-0.31, 0.0002, -1e-7], "max": [1.5, 2.25, 3e5]}),
                 "display": {"mode": "toon"},
                 "field": {"job": "00000000feedface", "artifact": "sdf", "map": "coolwarm", "range": [-0.125, 0.125]}}
        script = ("import { importTs } from './tests/ts_module.mjs';"
                  "const { decodeViewHash, encodeViewHash } = await importTs('viewer/view_state.ts');"
                  "const hash = process.argv[1];"
                  "const state = decodeViewHash(hash.split('&')[0]);"
                  "console.log(JSON.stringify({ again: encodeViewHash(state), state }));")
        hash_ = view_hash(state, ticket="cgt_x")
        out = subprocess.run(["node", "--input-type=module", "-e", script, hash_], cwd=WEB_CLIENT, check=True,
                             capture_output=True, text=True, timeout=60)
        answer = json.loads(out.stdout)
        self.assertEqual(answer["again"], hash_.split("&")[0])
        self.assertEqual(answer["state"], json.loads(js_json(state)))
        self.assertEqual(decode_view_hash(hash_), (json.loads(js_json(state)), {"ticket": "cgt_x"}))


class ShowOnLoopbackTest(unittest.TestCase):
    """A server on loopback without tokens: the view's link needs no ticket."""

    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server()
        cls.client = Client(cls.server.url)
        cls.mesh = cls.client.upload(harness.ELEPHANT)
        cls.job = cls.client.run("centroid_distance", cls.mesh, exponent=2.0, on_progress=False)

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()

    def check_view(self, data, width, height, field=True, mode=None):
        """The output's iframe opens the mesh (and the job's field) and its pictures are the render."""
        page = Frames(data["text/html"])
        [src] = page.iframes
        self.assertTrue(src.startswith(self.server.url + "/#view="), src)
        state, rest = decode_view_hash(fragment(src))
        self.assertEqual(rest, {})  # no token, no ticket on loopback
        self.assertEqual(state["v"], 1)
        self.assertEqual(state["mesh"], self.mesh.id)
        self.assertEqual(set(state["camera"]), {"position", "target", "up", "fov"})
        if field:
            artifact = self.job["artifacts"][0]
            self.assertEqual(artifact["hint"], "magnitude")  # which the viewer draws in turbo (colormaps.ts)
            self.assertEqual(state["field"], {"job": self.job.id, "artifact": artifact["name"], "map": "turbo",
                                              "range": artifact["range"]})
        else:
            self.assertNotIn("field", state)
        self.assertEqual(state.get("display"), {"mode": mode} if mode else None)
        # The picture: the PNG of the bundle, inlined in the HTML too, the render of the view's size.
        picture = base64.b64decode(data["image/png"])
        image = png.decode(picture)
        self.assertEqual((image.width, image.height), (width, height))
        [img] = page.images
        self.assertTrue(img.startswith("data:image/png;base64,"))
        self.assertEqual(base64.b64decode(img.split(",", 1)[1]), picture)
        if field:
            self.assertGreater(harness.colourful(image), 1000)  # coloured by the field
        params = {"width": width, "height": height, "azimuth": "30", "elevation": "20"}
        if field:
            params["field"] = f"{self.job.id}/{self.job['artifacts'][0]['name']}"
        if mode:
            params["mode"] = mode
        expected = self.client.render(self.mesh.id, **params)
        self.assertEqual(png.decode(expected).rgba, image.rgba)
        return state

    @unittest.skipIf(nbclient is None, "nbclient")
    def test_show_in_a_notebook(self):
        notebook = run_cells([
            "from cgview_client import Client\n"
            "c = Client()\n"
            f"mesh = c.mesh({self.mesh.id!r})\n"
            f"job = c.job({self.job.id!r})",
            "mesh.show(field=job, width=320, height=240)",
            "job.show(width=300, height=200, mode='flat')",
            f"mesh.show(field={self.job['artifacts'][0]['name']!r}, width=200, height=100)",
            "mesh.show(width=160, height=120)",
        ], {"CGVIEW_URL": self.server.url})
        _, by_job, from_job, by_name, plain = notebook.cells
        a = self.check_view(view_output(by_job), 320, 240)
        b = self.check_view(view_output(from_job), 300, 200, mode="flat")
        self.assertEqual(a["field"], b["field"])
        self.check_view(view_output(by_name), 200, 100)
        self.check_view(view_output(plain), 160, 120, field=False)
        # The picture is what shows without the viewer: the iframe waits hidden for the page's word.
        html = view_output(plain)["text/html"]
        self.assertIn("visibility:hidden", html)
        self.assertIn("cgview-embed", html)
        self.assertIn(">open in CGView</a>", html)

    def test_without_embedding_the_picture_alone(self):
        view = Client(self.server.url, embed=False).mesh(self.mesh.id).show(width=100, height=80)
        page = Frames(view._repr_html_())
        self.assertEqual(page.iframes, [])
        self.assertEqual(len(page.images), 1)
        self.assertEqual(png.decode(view._repr_png_()).width, 100)
        self.assertNotIn("<script", view._repr_html_())

    def test_the_browsers_address_for_the_server(self):
        view = Client(self.server.url, view_url="https://cgview.lab.example.org/").mesh(self.mesh.id).show()
        self.assertTrue(view.url().startswith("https://cgview.lab.example.org/#view="))
        self.assertIn("'https://cgview.lab.example.org'", view.html().replace('"', "'"))  # the messages' origin

    def test_a_job_without_a_field_shows_its_mesh_skeleton_or_grid(self):
        moved = self.client.run("orient_outward", self.mesh, on_progress=False)  # a mesh, no field
        self.assertNotIn("scalar_field", [a["kind"] for a in moved["artifacts"]])
        view = moved.show(width=64, height=48)
        state = view.state()
        self.assertEqual(state["mesh"], self.mesh.id)
        self.assertNotIn("field", state)
        [made] = [a["name"] for a in moved["artifacts"] if a["kind"] == "mesh"]
        # The output mesh in the scene as the viewer keeps a job's mesh, the input hidden.
        self.assertEqual(state["scene"], [{"mesh": self.mesh.id, "visible": False},
                                          {"mesh": f"job:{moved.id}/{made}", "visible": True}])
        self.assertIn(f"with its {made}", view.html())
        # A skeleton is drawn and a grid's slices open: the link's `show`.
        bone = self.client.upload_data_bytes(b"2 0 0 0 0 1 0\n", "bone.polylines.txt", self.mesh)
        grid = self.client.upload_data_bytes(
            b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n" + bytes(range(8)),
            "cube.nrrd", self.mesh)
        for job, kind in ((bone, "skeleton"), (grid, "voxel_grid")):
            [a] = job["artifacts"]
            self.assertEqual(a["kind"], kind)
            view = job.show(width=64, height=48)
            state, rest = decode_view_hash(fragment(view.url()))
            self.assertEqual(state["mesh"], self.mesh.id)
            self.assertEqual(rest, {"show": [f"{job.id}/{a['name']}"]})
            self.assertNotIn("scene", state)
        with self.assertRaises(LookupError):
            moved.show(artifact="nothing")
        with self.assertRaises(LookupError):
            self.mesh.show(field="no_such_field")
        with self.assertRaises(ValueError):
            self.mesh.show(mode="cartoon")


class ShowOffLoopbackTest(unittest.TestCase):
    """A server that needs a token (--auth required): show() gives the page a
    ticket; the token is in no output and no URL; the ticket works once."""

    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(users=("alice",), args=("--auth", "required"))
        cls.token = cls.server.tokens["alice"]
        cls.client = Client(cls.server.url, token=cls.token)
        cls.mesh = cls.client.upload(harness.ELEPHANT)
        cls.job = cls.client.run("centroid_distance", cls.mesh, on_progress=False)

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()

    @unittest.skipIf(nbclient is None, "nbclient")
    def test_show_in_a_notebook_gives_a_ticket_not_the_token(self):
        notebook = run_cells([
            "from cgview_client import Client\n"
            f"job = Client().job({self.job.id!r})",
            "job.show(width=240, height=180)",
            "from IPython.display import display\n"
            "display(job.show(width=120, height=90))\n"
            "display(job.show(width=120, height=90))",
        ], {"CGVIEW_URL": self.server.url, "CGVIEW_TOKEN": self.token})
        saved = nbformat.writes(notebook)
        secret = self.token.split("_")[-1]
        self.assertNotIn(secret, saved)  # in no output, no URL, no script: the saved notebook has none of it
        self.assertNotIn(self.token.split("_")[1], saved)  # not even the token's id
        tickets = []
        for cell in notebook.cells[1:]:
            outputs = [o["data"] for o in cell.outputs if "cgview-view" in o.get("data", {}).get("text/html", "")]
            for data in outputs:
                [src] = Frames(data["text/html"]).iframes
                state, rest = decode_view_hash(fragment(src))
                self.assertEqual(state["mesh"], self.mesh.id)
                self.assertEqual(state["field"]["job"], self.job.id)
                self.assertEqual(set(rest), {"ticket"})
                self.assertRegex(rest["ticket"], r"^cgt_[0-9a-f]{16}_[0-9a-f]{64}$")
                for link in Frames(data["text/html"]).links:  # "open in CGView": no ticket, no token
                    self.assertNotIn("ticket", link)
                tickets.append(rest["ticket"])
                self.assertEqual(png.decode(base64.b64decode(data["image/png"])).width,
                                 240 if cell is notebook.cells[1] else 120)
        self.assertEqual(len(tickets), 3)
        self.assertEqual(len(set(tickets)), 3)  # a ticket for each display
        # The page's ticket, redeemed without a token, is alice's session, once.
        status, session = post(self.server.url, "/tickets/redeem", {"ticket": tickets[0]})
        self.assertEqual(status, 200, session)
        self.assertEqual(session["user"], "alice")
        self.assertNotEqual(session["token"], self.token)
        self.assertEqual(Client(self.server.url, token=session["token"]).me()["user"], "alice")
        status, body = post(self.server.url, "/tickets/redeem", {"ticket": tickets[0]})
        self.assertEqual((status, body["error"]), (401, "unauthorized"))

    def test_a_ticket_works_once_and_not_after_it_expires_nor_forged(self):
        ticket = self.client.ticket()
        self.assertEqual(ticket["expires_s"], 60)
        self.assertEqual(post(self.server.url, "/tickets/redeem", {"ticket": ticket["ticket"]})[0], 200)
        self.assertEqual(post(self.server.url, "/tickets/redeem", {"ticket": ticket["ticket"]})[0], 401)
        short = self.client.ticket(expires_s=1)["ticket"]
        time.sleep(1.5)
        self.assertEqual(post(self.server.url, "/tickets/redeem", {"ticket": short})[0], 401)
        real = self.client.ticket()["ticket"]
        forged = real[:-1] + ("1" if real[-1] == "0" else "0")
        self.assertEqual(post(self.server.url, "/tickets/redeem", {"ticket": forged})[0], 401)
        self.assertEqual(post(self.server.url, "/tickets/redeem", {"ticket": real})[0], 401)  # tried once: gone
        self.assertEqual(post(self.server.url, "/tickets/redeem", {"ticket": "cgt_" + "0" * 16 + "_" + "0" * 64})[0],
                         401)
        # Making one needs the token; a session makes none.
        self.assertEqual(post(self.server.url, "/tickets", {})[0], 401)
        session = post(self.server.url, "/tickets/redeem", {"ticket": self.client.ticket()["ticket"]})[1]["token"]
        with self.assertRaises(CGViewError) as refused:
            Client(self.server.url, token=session).ticket()
        self.assertEqual(refused.exception.status, 403)
        with self.assertRaises(CGViewError) as bad:
            self.client.ticket(expires_s=600)
        self.assertEqual(bad.exception.status, 400)

    def test_the_view_object_outside_a_kernel(self):
        view = self.client.job(self.job.id).show(width=50, height=40)
        first, second = view.html(), view.html()
        ticket = re.compile(r"ticket=(cgt_[0-9a-f_]+)")
        self.assertNotEqual(ticket.search(first).group(1), ticket.search(second).group(1))
        self.assertNotIn(self.token, first + second + repr(view) + view.url())
        self.assertIsInstance(view, View)


if __name__ == "__main__":
    unittest.main()
