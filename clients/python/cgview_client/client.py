"""The CGView REST API (protocol/API.md) from Python's standard library."""
import json
import os
import re
import ssl
import time
import urllib.error
import urllib.parse
import urllib.request

from . import live

DEFAULT_URL = "http://127.0.0.1:8080"
TERMINAL_STATES = ("done", "failed", "cancelled", "interrupted")


class CGViewError(Exception):
    """An error answer of the server: HTTP status, error code, detail and,
    for a bad parameter, its name.  Over a quota (413 storage_quota, 429
    job_limit) the detail names the limit and the use, .limit and .used are
    the numbers, and for 429 .retry_after the seconds to wait."""

    def __init__(self, status, error, detail, parameter=None, limit=None, used=None, retry_after=None):
        super().__init__(f"HTTP {status} {error}: {detail}")
        self.status, self.error, self.detail, self.parameter = status, error, detail, parameter
        self.limit, self.used, self.retry_after = limit, used, retry_after


class JobFailed(Exception):
    """A job that ended in another state than done; .job is its last state."""

    def __init__(self, job):
        super().__init__(f"job {job['id']} ({job['algorithm']}) {job['state']}: {job.get('error') or 'no error given'}")
        self.job = job


class Client:
    """One server.  url: its address, http:// or https:// (default
    $CGVIEW_URL, else http://127.0.0.1:8080); token: a bearer token (default
    $CGVIEW_TOKEN; the server needs none from loopback unless it runs with
    --auth required); ca_file: the PEM certificate(s) to trust for https://
    instead of the system's (default $CGVIEW_CA_FILE), e.g. a self-signed
    server's own."""

    def __init__(self, url=None, token=None, timeout=300, ca_file=None):
        self.url = (url or os.environ.get("CGVIEW_URL") or DEFAULT_URL).rstrip("/")
        self.token = token if token is not None else os.environ.get("CGVIEW_TOKEN") or None
        self.timeout = timeout
        self.ca_file = ca_file or os.environ.get("CGVIEW_CA_FILE") or None
        self.ssl_context = ssl.create_default_context(cafile=self.ca_file) if self.ca_file else None

    # --- HTTP -----------------------------------------------------------
    def request(self, method, path, body=None, query=None, content_type=None):
        """The response's bytes and headers; a CGViewError for an error answer."""
        url = f"{self.url}/api/v1{path}"
        if query:
            url += "?" + urllib.parse.urlencode({k: v for k, v in query.items() if v is not None})
        headers = {}
        if self.token:
            headers["Authorization"] = f"Bearer {self.token}"
        if content_type:
            headers["Content-Type"] = content_type
        req = urllib.request.Request(url, data=body, method=method, headers=headers)
        try:
            with urllib.request.urlopen(req, timeout=self.timeout, context=self.ssl_context) as r:
                return r.read(), r.headers
        except urllib.error.HTTPError as e:
            raw = e.read()
            try:
                err = json.loads(raw)
            except ValueError:
                err = {"error": e.reason, "detail": raw.decode(errors="replace").strip()}
            retry = e.headers.get("Retry-After") if e.headers else None
            raise CGViewError(e.code, err.get("error"), err.get("detail"), err.get("parameter"), err.get("limit"),
                              err.get("used"), int(retry) if retry and retry.isdigit() else None) from None

    def get_json(self, path, query=None):
        return json.loads(self.request("GET", path, query=query)[0])

    def send_json(self, method, path, value):
        return json.loads(self.request(method, path, json.dumps(value).encode(), content_type="application/json")[0])

    # --- meshes ---------------------------------------------------------
    def health(self):
        return self.get_json("/health")

    def me(self):
        """Who the token is: user, admin, storage_bytes_used and _limit,
        jobs_active and jobs_limit (a limit is None where there is none)."""
        return self.get_json("/me")

    def share(self, kind, item_id, users=(), everyone=False, unshare=False):
        """Shares a mesh or a job (kind "meshes" or "jobs") with users and/or
        everyone, or takes that back; who reads it now."""
        return self.send_json("POST", f"/{kind}/{quote(item_id)}/{'unshare' if unshare else 'share'}",
                              {"users": list(users), "everyone": everyone})

    def meshes(self):
        return self.get_json("/meshes")["meshes"]

    def mesh(self, mesh_id):
        return self.get_json(f"/meshes/{quote(mesh_id)}")

    def upload(self, path, name=None):
        """Uploads a mesh file; the server's Mesh (id, name, report, ...)."""
        with open(path, "rb") as f:
            data = f.read()
        name = name or os.path.basename(path)
        return json.loads(self.request("POST", "/meshes", data, {"name": name}, "application/octet-stream")[0])

    def find_mesh(self, ref):
        """A mesh by id or by name (the newest of that name), or an upload of
        the file ref names; LookupError when it is none of them."""
        meshes = self.meshes()
        for m in [m for m in meshes if m["id"] == ref] or [m for m in reversed(meshes) if m["name"] == ref]:
            return m
        if os.path.isfile(ref):
            return self.upload(ref)
        raise LookupError(f"no mesh with id or name '{ref}' on {self.url}, and no file '{ref}'")

    def download_mesh(self, mesh_id, fmt="ply"):
        return self.request("GET", f"/meshes/{quote(mesh_id)}/download", query={"format": fmt})[0]

    def delete_mesh(self, mesh_id):
        self.request("DELETE", f"/meshes/{quote(mesh_id)}")

    def render(self, mesh_id, **params):
        """PNG bytes of the mesh from the server's renderer; params: mode,
        width, height, azimuth, elevation, projection, field ("JOB/ARTIFACT")."""
        return self.request("GET", f"/meshes/{quote(mesh_id)}/render.png", query=params)[0]

    # --- algorithms and jobs --------------------------------------------
    def algorithms(self):
        return self.get_json("/algorithms")["algorithms"]

    def jobs(self):
        return self.get_json("/jobs")["jobs"]

    def job(self, job_id):
        return self.get_json(f"/jobs/{quote(job_id)}")

    def submit(self, algorithm, mesh, params=None, inputs=None):
        """Submits a job on a mesh id (its input 'mesh'); inputs: the others by name."""
        body = {"algorithm": algorithm, "inputs": {"mesh": mesh, **(inputs or {})}, "params": params or {}}
        return self.send_json("POST", "/jobs", body)

    def cancel(self, job_id):
        return json.loads(self.request("DELETE", f"/jobs/{quote(job_id)}")[0])

    def wait(self, job_id, on_progress=None, timeout=None, use_websocket=True):
        """Waits for a job to end and returns its last state, whatever it is.
        on_progress(job) is called on each change: from the WebSocket's events
        when python3-websocket is there, else by polling."""
        deadline = None if timeout is None else time.monotonic() + timeout
        events = live.JobEvents(self.url, self.token, self.ca_file) if use_websocket else None
        try:
            if events is not None and not events.open():
                events = None
            job = self.job(job_id)  # after subscribing, so that no event is missed
            while True:
                if on_progress:
                    on_progress(job)
                if job["state"] in TERMINAL_STATES:
                    return job
                if deadline is not None and time.monotonic() > deadline:
                    raise TimeoutError(f"job {job_id} is still {job['state']} after {timeout} s")
                event = events.next_for(job_id, 1.0) if events else None
                if event is None:
                    if not (events and events.connected):
                        time.sleep(0.25)  # polling
                    job = self.job(job_id)  # no event for a while: ask
                elif event["state"] in TERMINAL_STATES and "artifacts" not in event:
                    job = self.job(job_id)
                else:
                    job = {**job, **event}
        finally:
            if events is not None:
                events.close()

    def run(self, algorithm, mesh, params=None, inputs=None, on_progress=None, timeout=None):
        """submit() then wait(); the done job, or JobFailed."""
        job = self.wait(self.submit(algorithm, mesh, params, inputs)["id"], on_progress, timeout)
        if job["state"] != "done":
            raise JobFailed(job)
        return job

    def artifact(self, job_id, name, fmt=None):
        """An artifact's bytes and its file name (NAME.FORMAT, as the server names it)."""
        data, headers = self.request("GET", f"/jobs/{quote(job_id)}/artifacts/{quote(name)}", query={"format": fmt})
        m = re.search(r'filename="([^"/\\]+)"', headers.get("Content-Disposition", ""))
        return data, m.group(1) if m else name

    def download(self, job_id, directory=".", names=None, fmt=None):
        """Writes a job's artifacts (all, or those named) into directory; their paths."""
        if names is None:
            names = [a["name"] for a in self.job(job_id)["artifacts"]]
        os.makedirs(directory, exist_ok=True)
        paths = []
        for name in names:
            data, file_name = self.artifact(job_id, name, fmt)
            paths.append(os.path.join(directory, file_name))
            with open(paths[-1], "wb") as f:
                f.write(data)
        return paths


def quote(segment):
    return urllib.parse.quote(segment, safe="")
