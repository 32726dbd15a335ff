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
from .errors import CGViewError, JobFailed
from . import params as parameters
from .algorithms import Algorithms
from .objects import Job, Mesh
from .teaching import Teaching

DEFAULT_URL = "http://127.0.0.1:8080"
TERMINAL_STATES = ("done", "failed", "cancelled", "interrupted")


class Client:
    """One server.  url: its address, http:// or https:// (default
    $CGVIEW_URL, else http://127.0.0.1:8080); token: a bearer token (default
    $CGVIEW_TOKEN; the server needs none from loopback unless it runs with
    --auth required); ca_file: the PEM certificate(s) to trust for https://
    instead of the system's (default $CGVIEW_CA_FILE), e.g. a self-signed
    server's own.  For show() in a notebook: view_url, the server's address
    as the notebook's browser reaches it (default $CGVIEW_VIEW_URL, else
    url); embed=False shows the server's picture alone, no live viewer."""

    def __init__(self, url=None, token=None, timeout=300, ca_file=None, view_url=None, embed=True):
        self.url = (url or os.environ.get("CGVIEW_URL") or DEFAULT_URL).rstrip("/")
        self.view_url = (view_url or os.environ.get("CGVIEW_VIEW_URL") or self.url).rstrip("/")
        self.embed = embed
        self.token = token if token is not None else os.environ.get("CGVIEW_TOKEN") or None
        self.timeout = timeout
        self.ca_file = ca_file or os.environ.get("CGVIEW_CA_FILE") or None
        self.ssl_context = ssl.create_default_context(cafile=self.ca_file) if self.ca_file else None
        # client.algorithms() lists them; client.algorithms.sdf(mesh, rays=25) runs one.
        self.algorithms = Algorithms(self)
        # client.courses() lists them; client.courses.submit(assignment, source=...) (teaching.py).
        self.courses = Teaching(self)

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

    def ticket(self, expires_s=None):
        """A sign-in ticket for this client's token, {"ticket", "expires_s"}:
        a page redeems it once, within expires_s (at most 60), for a session
        of the same user (protocol/API.md, "Sign-in tickets"); show() hands
        one to the viewer, so that no token goes into a URL."""
        return self.send_json("POST", "/tickets", {} if expires_s is None else {"expires_s": expires_s})

    def share(self, kind, item_id, users=(), everyone=False, unshare=False):
        """Shares a mesh or a job (kind "meshes" or "jobs") with users and/or
        everyone, or takes that back; who reads it now."""
        return self.send_json("POST", f"/{kind}/{quote(item_id)}/{'unshare' if unshare else 'share'}",
                              {"users": list(users), "everyone": everyone})

    def meshes(self):
        return [Mesh(self, m) for m in self.get_json("/meshes")["meshes"]]

    def mesh(self, mesh_id):
        return Mesh(self, self.get_json(f"/meshes/{quote(mesh_id)}"))

    def upload(self, path, name=None):
        """Uploads a mesh file; the server's Mesh (id, name, report, ...)."""
        with open(path, "rb") as f:
            data = f.read()
        return self.upload_bytes(data, name or os.path.basename(path))

    def upload_bytes(self, data, name):
        """Uploads a mesh file's bytes under a name (its extension says the format)."""
        return Mesh(self, json.loads(self.request("POST", "/meshes", data, {"name": name}, "application/octet-stream")[0]))

    def upload_arrays(self, vertices, faces, name="arrays.ply"):
        """Uploads a mesh from arrays, (n, 3) positions and (m, 3) triangle
        indices (numpy), without a file; the Mesh."""
        from . import arrays
        if not name.lower().endswith(".ply"):
            name += ".ply"
        return self.upload_bytes(arrays.ply_bytes(vertices, faces), name)

    def upload_open3d(self, mesh, name="open3d.ply"):
        """Uploads an open3d.geometry.TriangleMesh."""
        from . import interop
        return self.upload_arrays(*interop.from_open3d(mesh), name=name)

    def upload_meshio(self, mesh, name="meshio.ply"):
        """Uploads a meshio.Mesh of triangles."""
        from . import interop
        return self.upload_arrays(*interop.from_meshio(mesh), name=name)

    def upload_data(self, path, mesh=None, kind=None, property=None, name=None):
        """Uploads data another tool made, as meshes are uploaded: a voxel
        grid (.nrrd .binvox .vti .vox .vdb), a skeleton (.polylines.txt .cg
        .obj .json) or a scalar field for a stored mesh (.ply whose vertices
        or faces carry a property: the first, or `property`; .txt with one
        value a line; mesh= is required).  kind ("voxel_grid", "skeleton",
        "scalar_field") overrides the extension.  The done "import" Job whose
        one artifact is the data (job.grid(), job.skeleton(), job.field()),
        and an input of the next job ({"job": id, "artifact": name})."""
        with open(path, "rb") as f:
            data = f.read()
        return self.upload_data_bytes(data, name or os.path.basename(path), mesh, kind, property)

    def upload_data_bytes(self, data, name, mesh=None, kind=None, property=None):
        query = {"name": name}
        if mesh is not None:
            query["mesh"] = mesh["id"] if isinstance(mesh, dict) else mesh
        if kind:
            query["kind"] = kind
        if property:
            query["property"] = property
        return Job(self, json.loads(self.request("POST", "/data", data, query, "application/octet-stream")[0]))

    def upload_field(self, values, mesh, name="field"):
        """Uploads a scalar field from an array of one value per vertex, or
        per face, of a stored mesh (NaN: no value there); the import Job."""
        text = "".join(f"{float(v)!r}\n" for v in values)
        return self.upload_data_bytes(text.encode(), f"{name}.txt", mesh, "scalar_field")

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
    def jobs(self):
        return [Job(self, j) for j in self.get_json("/jobs")["jobs"]]

    def job(self, job_id):
        return Job(self, self.get_json(f"/jobs/{quote(job_id)}"))

    def submit(self, algorithm, mesh, params=None, inputs=None, **keywords):
        """Submits a job on a mesh (a Mesh or its id: the input 'mesh'; None
        for an algorithm that takes no mesh, as grid_surface and
        skeleton_distance); inputs: the others by name; parameters as
        params={...} or keywords (rays=25), checked against the algorithm's
        schema first (params.ParameterError names a misspelt one's closest
        match).  The Job."""
        given = {**(params or {}), **keywords}
        parameters.check(self.algorithms.describe(algorithm), given)
        named = {k: (v["id"] if isinstance(v, Mesh) else v) for k, v in (inputs or {}).items()}
        if mesh is not None:
            # A Mesh or the server's dict of one: its id; else an id, or a
            # {"job", "artifact"} that chains an earlier job's mesh.
            named = {"mesh": mesh["id"] if isinstance(mesh, dict) and "id" in mesh else mesh, **named}
        body = {"algorithm": algorithm, "inputs": named, "params": given}
        return Job(self, self.send_json("POST", "/jobs", body))

    def cancel(self, job_id):
        return json.loads(self.request("POST", f"/jobs/{quote(job_id)}/cancel", b"")[0])

    def delete_job(self, job_id):
        """Deletes an ended job and its results (a queued or running one is cancelled)."""
        self.request("DELETE", f"/jobs/{quote(job_id)}")

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

    def run(self, algorithm, mesh, params=None, inputs=None, on_progress=None, timeout=None, **keywords):
        """submit() then wait(): the done Job, or JobFailed; Ctrl-C cancels it.
        In a notebook an HTML progress bar shows (on_progress=False: none)."""
        return self.submit(algorithm, mesh, params, inputs, **keywords).result(timeout, on_progress)

    def map(self, algorithm, meshes, params=None, timeout=None, on_progress=None, **keywords):
        """Runs the algorithm on each mesh: submits them all, then waits for
        each; the done Jobs in the order of `meshes` (JobFailed for the first
        that failed).  Ctrl-C cancels those not ended.  In a notebook one HTML
        progress bar shows them all (on_progress=False: none)."""
        from .progress import NotebookProgressBar, default_progress
        jobs = [self.submit(algorithm, m, params, **keywords) for m in meshes]
        bar = default_progress(on_progress, total=len(jobs))
        try:
            done = []
            for job in jobs:
                if isinstance(bar, NotebookProgressBar) and done:
                    bar.next()
                # False, not None: the bar above, or none, and not a bar per job.
                done.append(job.result(timeout, bar or False))
            return done
        except KeyboardInterrupt:
            for job in jobs:
                if job.refresh()["state"] not in TERMINAL_STATES:
                    self.cancel(job.id)
            raise

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
