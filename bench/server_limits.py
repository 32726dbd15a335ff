#!/usr/bin/env python3
"""How far one server goes, and which limit stops it: open connections,
requests a second, jobs queued.  Run by hand on loopback, bounded in time;
the real cgview-server from build/bin, each part on a fresh data directory.

    python3 bench/server_limits.py                 # every part
    python3 bench/server_limits.py --only requests --seconds 5

- connections: idle WebSockets opened in batches, the server started under a
  login's soft limit of open files (1024, Debian's default) and its hard
  limit (--server-nofile): the server's RSS and a health request's time after
  each batch, until --connections or the first refusal, what refused, the
  server's CPU while out of descriptors and whether it serves once they close.
- requests: wrk on GET /api/v1/health and GET /api/v1/meshes (4 meshes) as
  the loopback local user (no rate limit), and as one token's holder (the
  per-token rate limit answers 429 past it).
- jobs: --jobs jobs submitted by 4 threads to a server with one job worker,
  so that they queue: submits a second, RSS per queued job, the job list's
  time at that size, and the cancel of them all.

Needs Debian's python3-websocket and wrk (setup.sh's test packages)."""
import argparse
import os
import re
import resource
import shutil
import subprocess
import sys
import threading
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, ".."))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))
sys.path.insert(0, os.path.join(REPO, "clients", "python", "tests"))

import harness  # noqa: E402  (the real server on a free port)
from cgview_client import CGViewError, Client  # noqa: E402

try:
    import websocket
except ImportError:
    sys.exit("server_limits: needs python3-websocket (Debian)")


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return 0.0


def open_files(pid):
    return len(os.listdir(f"/proc/{pid}/fd"))


def nofile_limit(pid):
    with open(f"/proc/{pid}/limits") as f:
        for line in f:
            if line.startswith("Max open files"):
                return int(line.split()[3])
    return -1


def cpu_s(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def health_ms(url, timeout=10):
    t = time.monotonic()
    with urllib.request.urlopen(url + "/api/v1/health", timeout=timeout) as r:
        r.read()
    return (time.monotonic() - t) * 1000


def start_server(nofile=None, args=(), users=()):
    if nofile is None:
        return harness.Server(args=args, users=users)
    # The harness starts harness.SERVER: point it at a wrapper that applies the limit.
    wrapper = os.path.join(os.environ.get("TMPDIR", "/tmp"), f"cgview-limits-{os.getpid()}.sh")
    with open(wrapper, "w") as f:
        f.write(f"#!/bin/sh\nexec prlimit --nofile={nofile[0]}:{nofile[1]} {harness.SERVER} \"$@\"\n")
    os.chmod(wrapper, 0o755)
    saved, harness.SERVER = harness.SERVER, wrapper
    try:
        return harness.Server(args=args, users=users)
    finally:
        harness.SERVER = saved


def connections(args):
    """Idle WebSockets until --connections or the first refusal."""
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))  # this client's own sockets
    want = min(args.connections, hard - 200)
    print(f"\n## Connections: idle WebSockets, up to {want} (client's open-file limit {hard})")
    server_hard = args.server_nofile or hard
    server = start_server(nofile=(min(1024, server_hard), server_hard),
                          args=["--ws-idle-timeout-s", "3600", "--idle-timeout-s", "3600"])
    pid = server.proc.pid
    try:
        print(f"server: open-file limit {nofile_limit(pid)} (started under soft 1024, hard {server_hard}); "
              f"RSS {rss_mb(pid):.1f} MB")
        ws_url = server.url.replace("http", "ws", 1) + "/api/v1/ws"
        sockets, refused, t0 = [], None, time.monotonic()
        print("| open | server RSS MB | server fds | health ms | s to open the batch |")
        print("|---:|---:|---:|---:|---:|")
        while len(sockets) < want and refused is None:
            tb = time.monotonic()
            for _ in range(min(args.batch, want - len(sockets))):
                try:
                    sockets.append(websocket.create_connection(ws_url, timeout=10))
                except Exception as e:  # noqa: BLE001  (what refused is the finding)
                    refused = f"{type(e).__name__}: {e}"
                    break
            if refused:
                # A server out of descriptors leaves new connections in the backlog: it must wait, not spin.
                before, t = cpu_s(pid), time.monotonic()
                time.sleep(3)
                print(f"| {len(sockets)} | {rss_mb(pid):.1f} | {open_files(pid)} | (waits) | "
                      f"{time.monotonic() - tb:.2f} |")
                print(f"server CPU while out of descriptors: {(cpu_s(pid) - before) / (time.monotonic() - t):.2f} cores")
                break
            print(f"| {len(sockets)} | {rss_mb(pid):.1f} | {open_files(pid)} | {health_ms(server.url):.1f} | "
                  f"{time.monotonic() - tb:.2f} |", flush=True)
        base = rss_mb(pid)
        print(f"held {len(sockets)} idle WebSockets in {time.monotonic() - t0:.1f} s; "
              f"refused: {refused or 'none'}")
        if refused:
            print("server said:", "".join(line for line in server.lines if "descriptor" in line or "open files" in line)
                  .strip() or "(nothing)")
        for s in sockets:
            s.close()
        time.sleep(2)
        print(f"after closing them: RSS {rss_mb(pid):.1f} MB (from {base:.1f}), fds {open_files(pid)}, "
              f"health {health_ms(server.url):.1f} ms")
    finally:
        server.stop()


def wrk(url, path, seconds, token=None, connections=32):
    cmd = ["wrk", "-t2", f"-c{connections}", f"-d{seconds}s", "--latency"]
    if token:
        cmd += ["-H", f"Authorization: Bearer {token}"]
    out = subprocess.run(cmd + [url + path], capture_output=True, text=True, check=True).stdout
    rps = float(re.search(r"Requests/sec:\s+([\d.]+)", out).group(1))
    dist = out[out.index("Latency Distribution"):]
    p50 = re.search(r"\s50%\s+(\S+)", dist).group(1)
    p99 = re.search(r"\s99%\s+(\S+)", dist).group(1)
    non2xx = re.search(r"Non-2xx or 3xx responses:\s+(\d+)", out)
    total = int(re.search(r"(\d+) requests in", out).group(1))
    return rps, p50, p99, int(non2xx.group(1)) if non2xx else 0, total


def requests(args):
    if not shutil.which("wrk"):
        print("\n## Requests: skipped (wrk is not installed)")
        return
    print(f"\n## Requests a second: wrk -t2 -c32 -d{args.seconds}s")
    print("| caller | route | requests/s | p50 | p99 | not 2xx | server CPU (cores) |")
    print("|---|---|---:|---:|---:|---:|---:|")
    for label, server_args, users in (("local user (loopback, no token)", [], ()),
                                      ("one token (--auth required)", ["--auth", "required"], ("alice",))):
        server = start_server(args=server_args, users=users)
        token = server.tokens.get("alice")
        try:
            c = Client(server.url, token=token)
            for name in ("elephant.off",) * 4:
                c.upload(os.path.join(harness.SAMPLES, name))
            for path in ("/api/v1/health", "/api/v1/meshes"):
                time.sleep(5)  # the token's bucket refills between runs
                before, t = cpu_s(server.proc.pid), time.monotonic()
                rps, p50, p99, non2xx, total = wrk(server.url, path, args.seconds, token)
                cores = (cpu_s(server.proc.pid) - before) / (time.monotonic() - t)
                print(f"| {label} | GET {path} | {rps:,.0f} | {p50} | {p99} | {non2xx} of {total} | {cores:.2f} |",
                      flush=True)
        finally:
            server.stop()


def jobs(args):
    n = args.jobs
    print(f"\n## Jobs queued: {n} jobs (centroid_distance, distinct parameters) on one job worker")
    server = start_server(args=["--job-workers", "1"])
    pid = server.proc.pid
    try:
        c = Client(server.url)
        mesh = c.upload(os.path.join(harness.SAMPLES, "elephant.off"))["id"]
        base = rss_mb(pid)
        ids, errors, lock = [], [], threading.Lock()

        def submit(k):
            for i in range(k, n, 4):
                try:
                    j = c.submit("centroid_distance", mesh, {"exponent": round(0.1 + 3.8 * i / n, 6)})
                    with lock:
                        ids.append(j["id"])
                except CGViewError as e:
                    with lock:
                        errors.append(str(e))

        t = time.monotonic()
        threads = [threading.Thread(target=submit, args=(k,)) for k in range(4)]
        for th in threads:
            th.start()
        for th in threads:
            th.join()
        took = time.monotonic() - t
        after = rss_mb(pid)
        t = time.monotonic()
        listed = c.get_json("/jobs")["jobs"]
        list_ms = (time.monotonic() - t) * 1000
        queued = sum(1 for j in listed if j.get("state") == "queued")
        print(f"submitted {len(ids)} in {took:.1f} s ({len(ids) / took:,.0f} a second), {len(errors)} refused"
              f"{': ' + errors[0] if errors else ''}")
        print(f"{queued} still queued; server RSS {base:.1f} -> {after:.1f} MB "
              f"({(after - base) * 1024 * 1024 / max(len(ids), 1):,.0f} bytes a job); "
              f"GET /api/v1/jobs ({len(listed)} jobs, {rss_mb(pid):.1f} MB RSS) took {list_ms:.0f} ms")
        t = time.monotonic()
        for i in ids:
            try:
                c.cancel(i)
            except CGViewError:
                pass  # ended meanwhile
        print(f"cancelled them in {time.monotonic() - t:.1f} s; health {health_ms(server.url):.1f} ms")
    finally:
        server.stop()


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--only", choices=["connections", "requests", "jobs"])
    p.add_argument("--connections", type=int, default=10000)
    p.add_argument("--batch", type=int, default=1000)
    p.add_argument("--server-nofile", type=int, help="the server's hard open-file limit (default: the client's)")
    p.add_argument("--seconds", type=int, default=10)
    p.add_argument("--jobs", type=int, default=2000)
    args = p.parse_args()
    for part in ("connections", "requests", "jobs"):
        if args.only in (None, part):
            globals()[part](args)


if __name__ == "__main__":
    main()
