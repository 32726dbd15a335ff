"""The real cgview-server for the client's tests: started on a free loopback
port with an empty data directory, stopped and removed afterwards.

Environment (CTest sets both): CGVIEW_SERVER (default build/bin/cgview-server),
CGVIEW_SAMPLES (default build/samples), both from the repository root."""
import json
import os
import re
import shutil
import ssl
import subprocess
import tempfile
import threading
import time
import unittest
import urllib.request

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLIENT_DIR = os.path.join(REPO, "clients", "python")
SERVER = os.environ.get("CGVIEW_SERVER") or os.path.join(REPO, "build", "bin", "cgview-server")
SAMPLES = os.environ.get("CGVIEW_SAMPLES") or os.path.join(REPO, "build", "samples")
ELEPHANT = os.path.join(SAMPLES, "elephant.off")


def self_signed(directory):
    """A certificate for localhost and 127.0.0.1 and its key (openssl): their paths."""
    cert, key = os.path.join(directory, "cert.pem"), os.path.join(directory, "key.pem")
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2", "-subj", "/CN=localhost",
                    "-addext", "subjectAltName=DNS:localhost,IP:127.0.0.1", "-keyout", key, "-out", cert],
                   check=True, capture_output=True)
    return cert, key


def add_user(data_dir, name):
    """`cgview-server user add NAME` on a data directory: the new token."""
    out = subprocess.run([SERVER, "--data-dir", data_dir, "user", "add", name], check=True, capture_output=True, text=True)
    return out.stdout.strip()


class Server:
    """`users`: names to create before the start, their tokens in self.tokens;
    `args`: more flags (--auth required)."""

    def __init__(self, timeout=30, users=(), args=(), ca_file=None):
        for path in (SERVER, ELEPHANT):
            if not os.path.exists(path):
                raise FileNotFoundError(f"{path} is missing: build first (cmake --build build)")
        self.data_dir = tempfile.mkdtemp(prefix="cgview-pyclient-")
        self.tokens = {name: add_user(self.data_dir, name) for name in users}
        self.proc = subprocess.Popen(
            [SERVER, "--host", "127.0.0.1", "--port", "0", "--data-dir", self.data_dir, "--samples", "none",
             "--job-workers", "2", *args],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.lines = []
        served = threading.Event()
        threading.Thread(target=self._read, args=(served,), daemon=True).start()
        if not served.wait(timeout):
            self.stop()
            raise RuntimeError(f"cgview-server did not say where it serves within {timeout} s:\n{self.log()}")
        self.url = re.search(r"CGView serving (https?://[^/\s]+)/", self.log()).group(1)
        self.context = ssl.create_default_context(cafile=ca_file) if ca_file else None
        self._wait_healthy(timeout)

    def _read(self, served):
        for line in self.proc.stdout:
            self.lines.append(line)
            if line.startswith("CGView serving"):
                served.set()

    def _wait_healthy(self, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.proc.poll() is not None:
                raise RuntimeError(f"cgview-server exited ({self.proc.returncode}):\n{self.log()}")
            try:
                request = urllib.request.Request(self.url + "/api/v1/health")
                if self.tokens:
                    request.add_header("Authorization", "Bearer " + next(iter(self.tokens.values())))
                with urllib.request.urlopen(request, timeout=2, context=self.context) as r:
                    if json.load(r).get("status") == "ok":
                        return
            except OSError:
                pass
            time.sleep(0.1)
        self.stop()
        raise RuntimeError(f"GET /api/v1/health did not answer ok within {timeout} s:\n{self.log()}")

    def log(self):
        return "".join(self.lines[-200:])

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        shutil.rmtree(self.data_dir, ignore_errors=True)


def start_module_server():
    """For setUpModule: one server for the module's tests, stopped at its end."""
    server = Server()
    unittest.addModuleCleanup(server.stop)
    return server


def colourful(image, threshold=0.25):
    """How many of an Image's pixels are clearly coloured (not grey or white):
    a scalar field's colour map shows, the plain surface does not."""
    count = 0
    for i in range(0, len(image.rgba), 4):
        r, g, b = image.rgba[i:i + 3]
        hi, lo = max(r, g, b), min(r, g, b)
        count += hi > 40 and hi - lo > threshold * hi
    return count
