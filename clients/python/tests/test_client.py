"""cgview_client.Client against the real cgview-server."""
import http.server
import json
import os
import shutil
import tempfile
import threading
import unittest
from unittest import mock

import harness
from cgview_client import CGViewError, Client, JobFailed, live, png, render_around

server = None


def setUpModule():
    global server
    server = harness.start_module_server()


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.client = Client(server.url)
        cls.mesh = cls.client.upload(harness.ELEPHANT)

    def test_health_and_upload(self):
        self.assertEqual(self.client.health()["status"], "ok")
        self.assertEqual(self.mesh["name"], "elephant.off")
        self.assertEqual(self.mesh["report"]["vertices"], 2775)
        self.assertIn(self.mesh["id"], [m["id"] for m in self.client.meshes()])
        self.assertEqual(self.client.mesh(self.mesh["id"])["sha256"], self.mesh["sha256"])

    def test_find_mesh_by_id_name_or_file(self):
        self.assertEqual(self.client.find_mesh(self.mesh["id"])["id"], self.mesh["id"])
        self.assertEqual(self.client.find_mesh("elephant.off")["id"], self.mesh["id"])
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "tetra.off")
            with open(path, "w") as f:
                f.write("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
            uploaded = self.client.find_mesh(path)
            self.assertEqual((uploaded["name"], uploaded["report"]["faces"]), ("tetra.off", 4))
            self.assertEqual(self.client.download_mesh(uploaded["id"], "off")[:3], b"OFF")
            self.client.delete_mesh(uploaded["id"])
        with self.assertRaisesRegex(LookupError, "no mesh with id or name 'nothing.off'"):
            self.client.find_mesh("nothing.off")

    def run_and_watch(self, exponent, use_websocket):
        # Each test its own exponent: a cached result would be done at once.
        job = self.client.submit("centroid_distance", self.mesh["id"], {"exponent": exponent})
        seen = []
        job = self.client.wait(job["id"], seen.append, timeout=120, use_websocket=use_websocket)
        self.assertEqual(job["state"], "done", job)
        self.assertEqual(seen[-1]["state"], "done")
        self.assertIn("artifacts", job)

    def test_wait_by_polling(self):
        self.run_and_watch(1.5, use_websocket=False)

    @unittest.skipIf(live.websocket is None, "python3-websocket is not installed")
    def test_wait_with_live_events(self):
        events = live.JobEvents(server.url)
        self.assertTrue(events.open(), "the WebSocket did not open")
        self.addCleanup(events.close)
        job = self.client.submit("centroid_distance", self.mesh["id"], {"exponent": 2.5})
        states = []
        while not states or states[-1] not in ("done", "failed"):
            event = events.next_for(job["id"], 30)
            self.assertIsNotNone(event, f"no event after {states}")
            states.append(event["state"])
        self.assertEqual(states[-1], "done")
        self.run_and_watch(3.5, use_websocket=True)

    def test_run_download_and_artifact_formats(self):
        job = self.client.run("curvature", self.mesh["id"])
        names = sorted(a["name"] for a in job["artifacts"])
        self.assertEqual(names, ["gaussian_curvature", "mean_curvature"])
        with tempfile.TemporaryDirectory() as d:
            paths = self.client.download(job["id"], d)
            self.assertEqual(sorted(os.path.basename(p) for p in paths),
                             ["gaussian_curvature.json", "mean_curvature.json"])
            with open(os.path.join(d, "mean_curvature.json")) as f:
                field = json.load(f)
            self.assertEqual((field["location"], len(field["values"])), ("vertex", 2775))
            [csv] = self.client.download(job["id"], d, ["mean_curvature"], "csv")
            self.assertTrue(csv.endswith("mean_curvature.csv"))
        self.assertEqual(self.client.job(job["id"])["state"], "done")
        self.assertIn(job["id"], [j["id"] for j in self.client.jobs()])

    def test_data_from_other_tools_comes_back_as_arrays(self):
        import numpy as np
        faces = self.mesh["report"]["faces"]
        values = np.arange(faces, dtype=np.float32) / faces
        values[5] = np.nan
        job = self.client.upload_field(values, self.mesh, name="wear")
        self.assertEqual((job["state"], job["algorithm"]), ("done", "import"))
        back = job.field("wear")
        self.assertEqual(back.shape, (faces,))
        self.assertTrue(np.isnan(back[5]))
        np.testing.assert_array_equal(np.delete(back, 5), np.delete(values, 5))
        self.assertEqual(job["warnings"], [f"1 of the {faces} values are missing (nan): those faces show no colour"])
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "tree.polylines.txt")
            with open(path, "w") as f:
                f.write("3 0 0 0 0 0 1 0 0 2\n2 0 0 1 1 0 1\n")
            skeleton = self.client.upload_data(path, mesh=self.mesh).skeleton()
            self.assertEqual((len(skeleton.nodes), len(skeleton.edges)), (4, 3))
        with self.assertRaisesRegex(CGViewError, "3 values, but the mesh has 2775 vertices"):
            self.client.upload_data_bytes(b"1\n2\n3\n", "few.txt", self.mesh)

    def test_errors_name_what_is_wrong(self):
        with self.assertRaises(CGViewError) as e:
            self.client.submit("centroid_distance", self.mesh["id"], {"exponent": 9})
        self.assertEqual((e.exception.status, e.exception.error), (400, "bad_request"))
        self.assertIn("parameter 'exponent'", str(e.exception))
        with self.assertRaises(CGViewError) as e:
            self.client.mesh("0000000000000000")
        self.assertEqual(e.exception.status, 404)
        with self.assertRaises(CGViewError) as e:
            self.client.render(self.mesh["id"], width=0)
        self.assertEqual(e.exception.parameter, "width")

    def test_cancel(self):
        job = self.client.submit("voxelize", self.mesh["id"], {"resolution": 1000})
        self.assertEqual(self.client.cancel(job["id"])["state"], "cancelled")
        self.assertEqual(self.client.wait(job["id"], timeout=60)["state"], "cancelled")
        # Cancelling again leaves it as it is; deleting it removes it.
        self.assertEqual(self.client.cancel(job["id"])["state"], "cancelled")
        self.client.delete_job(job["id"])
        with self.assertRaises(CGViewError) as e:
            self.client.job(job["id"])
        self.assertEqual(e.exception.status, 404)

    def test_run_raises_when_the_job_does_not_end_done(self):
        done = self.client.run("curvature", self.mesh["id"])
        with mock.patch.object(Client, "wait", return_value={**done, "state": "failed", "error": "boom"}):
            with self.assertRaisesRegex(JobFailed, "failed: boom"):
                self.client.run("curvature", self.mesh["id"])

    def test_render_and_views_around(self):
        job = self.client.run("centroid_distance", self.mesh["id"])
        plain = png.decode(self.client.render(self.mesh["id"], width=120, height=90))
        self.assertEqual((plain.width, plain.height), (120, 90))
        sheet = png.decode(render_around(self.client, self.mesh["id"], 4, 60, 50, field=f"{job['id']}/distance"))
        self.assertEqual((sheet.width, sheet.height), (240, 50))
        self.assertLess(harness.colourful(plain), 20)
        for i in range(4):  # the field's colours in each view
            view = png.Image(60, 50, b"".join(sheet.rgba[4 * (y * 240 + 60 * i):4 * (y * 240 + 60 * i + 60)]
                                              for y in range(50)))
            self.assertGreater(harness.colourful(view), 50, f"view {i}")


class QuotaTest(unittest.TestCase):
    """A config file with quotas: the client surfaces 413 and 429 with the
    server's message, the numbers and Retry-After."""

    @classmethod
    def setUpClass(cls):
        cls.config_dir = tempfile.mkdtemp(prefix="cgview-pyclient-config-")
        cls.addClassCleanup(shutil.rmtree, cls.config_dir, True)
        config = os.path.join(cls.config_dir, "config.json")
        with open(config, "w") as f:
            json.dump({"limits": {"storage_mb": 0.2, "concurrent_jobs": 1}}, f)  # one elephant (170 KB)
        cls.server = harness.Server(users=["erin"], args=["--auth", "required", "--config", config])
        cls.addClassCleanup(cls.server.stop)
        cls.client = Client(cls.server.url, token=cls.server.tokens["erin"])

    def test_over_the_storage_quota_and_the_job_cap(self):
        mesh = self.client.upload(harness.ELEPHANT)
        size = os.path.getsize(harness.ELEPHANT)
        me = self.client.me()
        self.assertEqual((me["user"], me["storage_bytes_used"], me["jobs_limit"]), ("erin", size, 1))
        with self.assertRaises(CGViewError) as caught:
            self.client.upload(harness.ELEPHANT, name="again.off")
        e = caught.exception
        self.assertEqual((e.status, e.error, e.used, e.limit), (413, "storage_quota", size, round(0.2 * 2**20)))
        self.assertIn("storage quota of 204.8 KB exceeded: 169.7 KB used, this upload is 169.7 KB", str(e))
        self.assertEqual([m["id"] for m in self.client.meshes()], [mesh["id"]])

        job = self.client.submit("voxelize", mesh["id"], {"resolution": 1000})
        try:
            with self.assertRaises(CGViewError) as caught:
                self.client.submit("voxelize", mesh["id"], {"resolution": 999})
            e = caught.exception
            self.assertEqual((e.status, e.error, e.limit, e.used), (429, "job_limit", 1, 1))
            self.assertIn("concurrent job limit of 1 reached", e.detail)
            self.assertGreater(e.retry_after, 0)
        finally:
            self.client.cancel(job["id"])


class TlsTest(unittest.TestCase):
    """A server with its own TLS (--tls-cert, --tls-key) and a self-signed
    certificate: the client trusts it with ca_file, over REST and the
    WebSocket; without it, the certificate is refused."""

    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="cgview-tls-")
        cls.addClassCleanup(shutil.rmtree, cls.dir, True)
        cls.cert, key = harness.self_signed(cls.dir)
        cls.server = harness.Server(args=["--tls-cert", cls.cert, "--tls-key", key], ca_file=cls.cert)
        cls.addClassCleanup(cls.server.stop)

    def test_https_and_wss_with_the_servers_certificate(self):
        self.assertTrue(self.server.url.startswith("https://"), self.server.url)
        client = Client(self.server.url, ca_file=self.cert)
        self.assertEqual(client.health()["status"], "ok")
        mesh = client.upload(harness.ELEPHANT)
        job = client.wait(client.submit("centroid_distance", mesh["id"])["id"], timeout=120,
                          use_websocket=live.websocket is not None)
        self.assertEqual(job["state"], "done", job)
        if live.websocket is not None:
            events = live.JobEvents(self.server.url, ca_file=self.cert)
            self.assertTrue(events.open(), "the WebSocket over TLS did not open")
            events.close()

    def test_an_untrusted_certificate_is_refused(self):
        with mock.patch.dict(os.environ, {"CGVIEW_CA_FILE": "", "SSL_CERT_FILE": "/nonexistent"}):
            with self.assertRaises(OSError) as caught:
                Client(self.server.url).health()
        self.assertIn("CERTIFICATE_VERIFY_FAILED", str(caught.exception))


class AuthRequiredTest(unittest.TestCase):
    """A server with --auth required: the client's token opens it, over REST
    and the WebSocket; without one, or with a wrong one, 401."""

    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(users=["alice", "bob"], args=["--auth", "required"])
        cls.addClassCleanup(cls.server.stop)

    def test_no_token_or_a_wrong_one_is_refused(self):
        for token in ("", "cgv_0123456789abcdef_" + "0" * 64):
            with mock.patch.dict(os.environ, {"CGVIEW_TOKEN": ""}):
                with self.assertRaises(CGViewError) as caught:
                    Client(self.server.url, token=token or None).meshes()
            self.assertEqual(caught.exception.status, 401)

    def test_a_users_token_runs_a_job_with_live_progress_and_sees_only_its_own(self):
        alice = Client(self.server.url, token=self.server.tokens["alice"])
        bob = Client(self.server.url, token=self.server.tokens["bob"])
        mesh = alice.upload(harness.ELEPHANT)
        seen = []
        job = alice.wait(alice.submit("centroid_distance", mesh["id"])["id"], seen.append, timeout=120,
                         use_websocket=live.websocket is not None)
        self.assertEqual(job["state"], "done", job)
        self.assertEqual(seen[-1]["state"], "done")
        self.assertNotIn(mesh["id"], [m["id"] for m in bob.meshes()])
        with self.assertRaises(CGViewError) as caught:
            bob.submit("centroid_distance", mesh["id"])
        self.assertEqual(caught.exception.status, 404)

    @unittest.skipIf(live.websocket is None, "python3-websocket is not installed")
    def test_the_websocket_takes_the_token(self):
        events = live.JobEvents(self.server.url, token=self.server.tokens["alice"])
        self.assertTrue(events.open(), "the WebSocket did not open with alice's token")
        events.close()


class Recorder(http.server.BaseHTTPRequestHandler):
    """Answers every GET with {} and keeps each request's Authorization."""
    seen = []

    def do_GET(self):
        Recorder.seen.append(self.headers.get("Authorization"))
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.end_headers()
        self.wfile.write(b"{}")

    def log_message(self, *args):
        pass


class TokenTest(unittest.TestCase):
    def setUp(self):
        self.http = http.server.HTTPServer(("127.0.0.1", 0), Recorder)
        threading.Thread(target=self.http.serve_forever, daemon=True).start()
        self.addCleanup(self.http.server_close)
        self.addCleanup(self.http.shutdown)
        self.url = f"http://127.0.0.1:{self.http.server_port}"
        Recorder.seen = []

    def test_bearer_token_from_argument_or_environment(self):
        with mock.patch.dict(os.environ, {"CGVIEW_TOKEN": "from-env"}):
            Client(self.url, token="given").health()
            Client(self.url).health()
        with mock.patch.dict(os.environ, {"CGVIEW_TOKEN": ""}):
            Client(self.url).health()
        self.assertEqual(Recorder.seen, ["Bearer given", "Bearer from-env", None])

    def test_url_from_environment(self):
        with mock.patch.dict(os.environ, {"CGVIEW_URL": self.url + "/"}):
            self.assertEqual(Client().url, self.url)
            Client().health()
        self.assertEqual(len(Recorder.seen), 1)


if __name__ == "__main__":
    unittest.main()
