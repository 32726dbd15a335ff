#!/usr/bin/env python3
"""A lab's day, as a soak test, run by hand on loopback and bounded in time.

Starts the real cgview-server (--auth required, one token per simulated
user, so each has its own rate limit as in a lab), then for --minutes:
--users users each loop over uploads (good, bad and large), WebSocket mesh
streams, jobs (some cancelled), renders and abruptly dropped connections,
while --idle more WebSockets stay connected and silent (answering pings).
Afterwards: the server is up, every answer was a documented status within
its time limit, no job is stuck, RSS over time, and after a clean stop
`PRAGMA integrity_check` is ok and every mesh record has its blob and every
blob its record.

    python3 tests/soak/soak.py                       # 50 users, 500 idle WebSockets, 10 minutes
    python3 tests/soak/soak.py --users 5 --idle 20 --minutes 0.5   # a quick look

Needs Debian's python3-websocket; the server from build/bin."""
import argparse
import collections
import json
import os
import random
import socket
import sqlite3
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))
sys.path.insert(0, os.path.join(REPO, "clients", "python", "tests"))

import harness  # noqa: E402  (the real server on a free port)
from cgview_client import CGViewError, Client  # noqa: E402

try:
    import websocket
except ImportError:
    sys.exit("soak: needs python3-websocket (Debian)")

# What a request may answer: success, or a documented refusal.
DOCUMENTED = {200, 201, 400, 404, 408, 413, 429, 503, 507}
REQUEST_LIMIT_S = 30


class Tally:
    def __init__(self):
        self.lock = threading.Lock()
        self.statuses = collections.Counter()
        self.undocumented = []
        self.latency = collections.defaultdict(list)
        self.counts = collections.Counter()

    def note(self, what, status, seconds, detail=""):
        with self.lock:
            self.statuses[(what, status)] += 1
            self.latency[what].append(seconds)
            if status not in DOCUMENTED or seconds > REQUEST_LIMIT_S:
                self.undocumented.append((what, status, round(seconds, 2), detail[:200]))

    def count(self, what, n=1):
        with self.lock:
            self.counts[what] += n


def timed(tally, what, call):
    t0 = time.monotonic()
    try:
        out = call()
        tally.note(what, 200, time.monotonic() - t0)
        return out
    except CGViewError as e:
        tally.note(what, e.status, time.monotonic() - t0, str(e))
    except Exception as e:  # a dropped or refused connection: no answer at all
        tally.note(what, 0, time.monotonic() - t0, repr(e))
    return None


def ws_url(url):
    return "ws" + url[len("http"):] + "/api/v1/ws"


def stream_mesh(url, token, mesh_id):
    """get_mesh over a WebSocket to its mesh_end; the binary frames' bytes."""
    ws = websocket.create_connection(ws_url(url), header=[f"Authorization: Bearer {token}"], timeout=REQUEST_LIMIT_S)
    try:
        ws.send(json.dumps({"type": "get_mesh", "request_id": 1, "mesh_id": mesh_id}))
        got = 0
        while True:
            op, data = ws.recv_data()
            if op == websocket.ABNF.OPCODE_BINARY:
                got += len(data)
            else:
                msg = json.loads(data)
                if msg.get("type") == "error":
                    raise CGViewError(404 if msg.get("error") == "not_found" else 400, msg.get("error"), msg.get("detail"))
                if msg.get("type") == "mesh_end":
                    return got
    finally:
        ws.close()


def drop_abruptly(port):
    """Half a request, then a reset."""
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    s.sendall(b"POST /api/v1/meshes?name=x.off HTTP/1.1\r\nHost: x\r\nContent-Length: 100000\r\n\r\nOFF\n3 1")
    s.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
    s.close()


def large_ply(n):
    """A binary PLY of a n x n grid of triangles."""
    import struct
    verts = b"".join(struct.pack("<3f", i % n, i // n, 0.0) for i in range(n * n))
    faces = bytearray()
    for y in range(n - 1):
        for x in range(n - 1):
            a = y * n + x
            faces += struct.pack("<B3i", 3, a, a + 1, a + n) + struct.pack("<B3i", 3, a + 1, a + n + 1, a + n)
    tris = 2 * (n - 1) * (n - 1)
    head = (f"ply\nformat binary_little_endian 1.0\nelement vertex {n * n}\nproperty float x\nproperty float y\n"
            f"property float z\nelement face {tris}\nproperty list uchar int vertex_indices\nend_header\n").encode()
    return head + verts + bytes(faces)


def user_day(url, port, token, until, tally, samples, rng):
    c = Client(url, token=token, timeout=REQUEST_LIMIT_S)
    mine, jobs = [], []
    large = large_ply(300)  # 179,402 triangles, 3.0 MB
    while time.monotonic() < until:
        action = rng.choices(["upload", "bad", "large", "stream", "job", "cancel", "render", "drop", "list"],
                             weights=[10, 4, 1, 12, 10, 4, 6, 3, 8])[0]
        tally.count(action)
        if action == "upload":
            name = rng.choice(samples)
            m = timed(tally, "upload", lambda: c.upload(os.path.join(harness.SAMPLES, name)))
            if m:
                mine.append(m["id"])
        elif action == "bad":
            junk = rng.choice([os.urandom(rng.randint(10, 5000)), b"OFF\n3 1 0\n0 0 0\n1 0 0\n", b"ply\nformat ascii 1.0\n"])
            timed(tally, "upload_bad", lambda: c.upload_bytes(junk, rng.choice(["bad.ply", "bad.off", "bad.stl", "bad.glb"])))
        elif action == "large":
            m = timed(tally, "upload_large", lambda: c.upload_bytes(large, "grid.ply"))
            if m:
                mine.append(m["id"])
        elif action == "stream" and mine:
            n = timed(tally, "ws_stream", lambda: stream_mesh(url, token, rng.choice(mine)))
            if n:
                tally.count("streamed_bytes", n)
        elif action == "job" and mine:
            algorithm, params = rng.choice([("centroid_distance", {"exponent": round(rng.uniform(0.1, 4), 3)}),
                                            ("sdf", {"rays": rng.randint(5, 30)}), ("curvature", {})])
            j = timed(tally, "job_submit", lambda: c.submit(algorithm, rng.choice(mine), params))
            if j:
                jobs.append(j["id"])
        elif action == "cancel" and jobs:
            timed(tally, "job_cancel", lambda: c.cancel(rng.choice(jobs)))
        elif action == "render" and mine:
            timed(tally, "render", lambda: c.render(rng.choice(mine), width=160, height=120))
        elif action == "drop":
            try:
                drop_abruptly(port)
            except OSError:
                pass
            if mine and rng.random() < 0.5:  # a WebSocket cut mid-stream
                try:
                    ws = websocket.create_connection(ws_url(url), header=[f"Authorization: Bearer {token}"], timeout=5)
                    ws.send(json.dumps({"type": "get_mesh", "request_id": 1, "mesh_id": rng.choice(mine)}))
                    ws.sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, b"\x01\x00\x00\x00\x00\x00\x00\x00")
                    ws.sock.close()
                except Exception:
                    pass
        elif action == "list":
            timed(tally, "list", lambda: (c.meshes(), c.jobs()))
        time.sleep(rng.uniform(0.05, 0.5))  # a person, not a loop
    return jobs


def idle_socket(url, token, stop, tally):
    try:
        ws = websocket.create_connection(ws_url(url), header=[f"Authorization: Bearer {token}"], timeout=None)
    except Exception as e:
        tally.note("idle_connect", 0, 0, repr(e))
        return
    tally.count("idle_open")
    ws.settimeout(1.0)
    while not stop.is_set():
        try:
            ws.recv_data(control_frame=True)  # answers the server's pings with pongs
        except websocket.WebSocketTimeoutException:
            continue
        except Exception as e:
            if not stop.is_set():  # the server closed it during the day, not at its end
                tally.note("idle_dropped", 0, 0, repr(e))
            return
    ws.close()


def rss_kb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return -1


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--users", type=int, default=50)
    p.add_argument("--idle", type=int, default=500)
    p.add_argument("--minutes", type=float, default=10)
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    names = [f"u{i}" for i in range(a.users)]
    server = harness.Server(users=names, args=["--auth", "required", "--job-timeout-s", "120"], timeout=60)
    port = int(server.url.rsplit(":", 1)[1])
    tally, stop = Tally(), threading.Event()
    samples = ["elephant.off", "sphere.off", "bunny00.off", "cactus.off", "camel.off"]
    t0 = time.monotonic()
    until = t0 + a.minutes * 60
    idle = [threading.Thread(target=idle_socket, args=(server.url, server.tokens[names[i % a.users]], stop, tally), daemon=True)
            for i in range(a.idle)]
    for t in idle:
        t.start()
    results = {}
    users = [threading.Thread(target=lambda n=n, i=i: results.__setitem__(n, user_day(server.url, port, server.tokens[n], until, tally,
                                                                                      samples, random.Random(a.seed * 1000 + i))),
                              daemon=True) for i, n in enumerate(names)]
    for t in users:
        t.start()
    rss = []
    while any(t.is_alive() for t in users):
        rss.append((round(time.monotonic() - t0), rss_kb(server.proc.pid)))
        time.sleep(5)
    for t in users:
        t.join()
    # No job stuck: every job ends (or was cancelled) within its limit.
    admin = {n: Client(server.url, token=server.tokens[n]) for n in names}
    stuck, deadline = [], time.monotonic() + 180
    for n, c in admin.items():
        for job_id in results.get(n, []):
            while True:
                state = c.job(job_id)["state"]
                if state not in ("queued", "running"):
                    break
                if time.monotonic() > deadline:
                    stuck.append((job_id, state))
                    break
                time.sleep(0.5)
    health = Client(server.url, token=server.tokens[names[0]]).health()
    stop.set()
    for t in idle:
        t.join(5)
    open_idle = tally.counts["idle_open"]
    dropped_idle = sum(1 for u in tally.undocumented if u[0] == "idle_dropped")
    server.proc.terminate()
    server.proc.wait(30)
    db = sqlite3.connect(os.path.join(server.data_dir, "cgview.db"))
    integrity = db.execute("PRAGMA integrity_check").fetchone()[0]
    records = {r[0] for r in db.execute("SELECT id FROM meshes")}
    blob_dir = os.path.join(server.data_dir, "blobs")
    blobs = {f.split(".")[0] for f in os.listdir(blob_dir)} if os.path.isdir(blob_dir) else set()
    without_blob, without_record = records - blobs, blobs - records
    # Report.
    warm = [r for t, r in rss if t >= 60] or [r for _, r in rss]
    third = max(1, len(warm) // 3)
    first, last = sorted(warm[:third])[third // 2], sorted(warm[-third:])[third // 2]
    print(f"# soak: {a.users} users, {a.idle} idle WebSockets, {a.minutes} min\n")
    print("| request | answers | p50 ms | p99 ms | max ms |\n|---|---|---:|---:|---:|")
    for what in sorted(tally.latency):
        ls = sorted(tally.latency[what])
        answers = ", ".join(f"{s}: {k}" for (w, s), k in sorted(tally.statuses.items()) if w == what)
        print(f"| {what} | {answers} | {ls[len(ls) // 2] * 1000:.0f} | {ls[int(len(ls) * 0.99)] * 1000:.0f} | {ls[-1] * 1000:.0f} |")
    print(f"\nactions: {dict(tally.counts)}")
    print(f"idle WebSockets open: {open_idle} of {a.idle}; dropped by the server: {dropped_idle}")
    print(f"RSS (kB) every 5 s: {[r for _, r in rss]}")
    print(f"RSS after warm-up: median of the first third {first} kB, of the last third {last} kB ({(last - first) / max(first, 1):+.1%})")
    print(f"health at the end: {health.get('status')}; jobs stuck: {stuck}")
    print(f"integrity_check: {integrity}; meshes {len(records)}, without blob {sorted(without_blob)}, blobs without record {sorted(without_record)}")
    bad = [u for u in tally.undocumented if u[0] not in ("idle_dropped",)]
    print(f"undocumented or late answers: {len(bad)}")
    for u in bad[:20]:
        print(f"  {u}")
    ok = (health.get("status") == "ok" and not stuck and integrity == "ok" and not without_blob and not without_record
          and not bad and dropped_idle == 0)
    print("\nSOAK", "PASSED" if ok else "FAILED")
    server.stop()
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
