"""A view in a notebook: `mesh.show()` or `job.show()` displays the real
viewer in the output cell (an iframe on the server's page, opened on that
mesh and field through the view link the viewer itself writes, `#view=...`,
web-client/src/viewer/view_state.ts), over the server's picture of the same
view (render.png, inlined), which is what shows where the viewer cannot be
reached: an exported notebook, a server that is down, a front end that runs
no scripts.

Off loopback the page needs to sign in, and a token must not go into a URL
(nor into a saved notebook): the kernel asks for a sign-in ticket
(POST /api/v1/tickets), good once and for a minute, which the page redeems
for a session of the same user (web-client/src/api/tickets.ts).  The
ticket rides in the hash, which browsers never send to a server."""
import base64
import decimal
import html
import json
import math
import uuid

from .errors import CGViewError

# What render.png and the view link share: the viewer's field of view and
# render.png's default side (azimuth about +y, elevation), so that the live
# view opens where the picture was taken.
FOV = 40.0
AZIMUTH, ELEVATION = 30.0, 20.0
# The viewer's colour map for a field's hint (web-client/src/viewer/colormaps.ts, defaultMapFor).
DEFAULT_MAPS = {"symmetric": "coolwarm", "categorical": "tab10", "magnitude": "turbo"}
# render.png's modes, which are the viewer's too.
MODES = ("points", "wireframe", "flat", "smooth", "toon")


# --- the view link, byte for byte as the viewer writes it ---------------------
def js_number(x):
    """A number as JavaScript's JSON.stringify writes it (ECMAScript's
    Number::toString: the shortest digits that read back, 1e21 and 1e-7 in
    exponent form, 2 not 2.0)."""
    if isinstance(x, bool):
        raise TypeError("a bool is not a number here")
    x = float(x)
    if not math.isfinite(x):
        return "null"
    if x == 0:
        return "0"
    sign, places, exponent = decimal.Decimal(repr(x)).as_tuple()  # repr: the shortest digits, as JavaScript's
    written = "".join(map(str, places))
    digits = written.rstrip("0")
    exponent += len(written) - len(digits)
    k, n = len(digits), exponent + len(digits)  # the digits, and where the point goes after the first n
    if k <= n <= 21:
        text = digits + "0" * (n - k)
    elif 0 < n <= 21:
        text = digits[:n] + "." + digits[n:]
    elif -6 < n <= 0:
        text = "0." + "0" * -n + digits
    else:
        e = n - 1
        text = digits[0] + ("." + digits[1:] if k > 1 else "") + "e" + ("+" if e > 0 else "-") + str(abs(e))
    return ("-" if sign else "") + text


def js_json(value):
    """JSON.stringify(value) for dicts (in their order), lists, strings, numbers, booleans and None."""
    if value is None or isinstance(value, bool):
        return json.dumps(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)  # JSON.stringify escapes the same characters
    if isinstance(value, (int, float)):
        return js_number(value)
    if isinstance(value, dict):
        return "{" + ",".join(js_json(str(k)) + ":" + js_json(v) for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ",".join(js_json(v) for v in value) + "]"
    raise TypeError(f"{type(value).__name__} is not JSON")


def view_hash(state, ticket=None, shows=()):
    """The page hash (with its '#') that opens `state` (a ViewState: v, mesh,
    camera, display, field...), as the viewer's encodeViewHash writes it;
    `shows`: "JOB/ARTIFACT" keys of skeletons to draw and a voxel grid whose
    slices to open (the hash's `show=`, controllers/view_links.ts); with a
    ticket, `&ticket=` after it for the page to sign in with."""
    from urllib.parse import quote
    b64 = base64.urlsafe_b64encode(js_json(state).encode()).decode().rstrip("=")
    return (f"#view={b64}" + "".join(f"&show={quote(k, safe='')}" for k in shows) +
            (f"&ticket={ticket}" if ticket else ""))


def decode_view_hash(hash_):
    """The ViewState and the other parameters of a page hash (tests, and to read a link)."""
    from urllib.parse import parse_qs
    params = parse_qs(hash_.lstrip("#"), keep_blank_values=True)
    b64 = params.pop("view")[0]
    state = json.loads(base64.urlsafe_b64decode(b64 + "=" * (-len(b64) % 4)))
    return state, {k: (v if k == "show" else v[0]) for k, v in params.items()}


def camera(bbox, azimuth=AZIMUTH, elevation=ELEVATION, fov=FOV):
    """The viewer's camera (position, target, up, fov) looking at a mesh's
    bounding box ({"min": [x, y, z], "max": [...]}) from render.png's side,
    far enough that its bounding sphere fits a square view (a wider one shows
    more around it)."""
    lo, hi = bbox["min"], bbox["max"]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    radius = max(0.5 * math.dist(lo, hi), 1e-6)
    az, el = math.radians(azimuth), math.radians(elevation)
    direction = [math.cos(el) * math.sin(az), math.sin(el), math.cos(el) * math.cos(az)]
    distance = radius / math.sin(math.radians(fov) / 2) * 1.05  # the viewer's frameBox margin
    return {"position": [c + d * distance for c, d in zip(centre, direction)], "target": centre,
            "up": [0, 1, 0], "fov": fov}


# --- what a view shows -----------------------------------------------------------
def _field_artifact(job, name=None):
    """A done job's scalar field artifact (the first, or the one named): its JSON."""
    for a in job.get("artifacts") or []:
        if a.get("kind") == "scalar_field" and (name is None or a["name"] == name):
            return a
    return None


def field_state(client, job, artifact):
    """The view link's field: its job, artifact, the map the viewer gives its
    hint and its range (symmetric about 0 for a symmetric hint), as the viewer
    draws it when opened by hand."""
    rng = artifact.get("range")
    finite = isinstance(rng, list) and len(rng) == 2 and all(
        isinstance(v, (int, float)) and math.isfinite(v) for v in rng)
    if not finite:
        values = json.loads(client.artifact(job["id"], artifact["name"], "json")[0])
        rng = values.get("range") or [0, 0]
    rng = [float(rng[0]), float(rng[1])]
    if artifact.get("hint") == "symmetric":
        m = max(abs(rng[0]), abs(rng[1]))
        rng = [-m, m]
    return {"job": job["id"], "artifact": artifact["name"], "map": DEFAULT_MAPS.get(artifact.get("hint"), "viridis"),
            "range": rng}


class View:
    """A mesh (and a field on it) in a notebook's output: the viewer live in
    an iframe where the page can reach the server, the server's picture where
    it cannot (IPython shows it: the last expression of a cell, or
    display(view)).  .url() is the view's link, .png() the picture's bytes,
    .html() the output's HTML."""

    def __init__(self, client, mesh, field=None, mode=None, width=800, height=500, caption=None, scene=None,
                 shows=()):
        if mode is not None and mode not in MODES:
            raise ValueError(f"mode must be one of {', '.join(MODES)}, not {mode!r}")
        self.client, self.mesh, self.field, self.mode = client, mesh, field, mode
        self.width, self.height = int(width), int(height)
        self.caption = caption
        self.scene, self.shows = scene, tuple(shows)
        self._png = None

    def state(self):
        """The ViewState the link holds (view_state.ts)."""
        state = {"v": 1, "mesh": self.mesh["id"], "camera": camera(self.mesh["report"]["bbox"])}
        if self.mode:
            state["display"] = {"mode": self.mode}
        if self.field:
            state["field"] = self.field
        if self.scene:
            state["scene"] = self.scene
        return state

    def url(self, ticket=None):
        """The viewer's address opened on this view (for the browser: the
        client's view_url); with a ticket, one the page signs in with."""
        return f"{self.client.view_url}/{view_hash(self.state(), ticket, self.shows)}"

    def png(self):
        """The server's picture of the view (render.png, the view's size), fetched once."""
        if self._png is None:
            params = {"width": self.width, "height": self.height, "azimuth": f"{AZIMUTH:g}",
                      "elevation": f"{ELEVATION:g}"}
            if self.mode:
                params["mode"] = self.mode
            if self.field:
                params["field"] = f"{self.field['job']}/{self.field['artifact']}"
            self._png = self.client.render(self.mesh["id"], **params)
        return self._png

    def _ticket(self):
        """A new ticket when the client has a token (each display its own: a ticket works once); else None."""
        if not self.client.token:
            return None
        return self.client.ticket()["ticket"]

    def title(self):
        title = self.mesh.get("name") or self.mesh["id"]
        if self.field:
            title += f" · {self.field['artifact']}"
        return self.caption or title

    def html(self):
        """The output's HTML: the picture, and the live viewer over it once
        its page says it has signed in (a script in the output listens for
        its message); the picture alone with Client(embed=False)."""
        picture = base64.b64encode(self.png()).decode()
        size = f"width:{self.width}px;height:{self.height}px;max-width:100%"
        alt = html.escape(self.title(), quote=True)
        img = (f'<img alt="{alt}" src="data:image/png;base64,{picture}" '
               f'style="position:absolute;left:0;top:0;width:100%;height:100%;object-fit:contain">')
        link = html.escape(self.url(), quote=True)  # without a ticket: for a browser already signed in
        caption = (f'<div class="cgview-caption" style="font:12px sans-serif;color:#666">{html.escape(self.title())}'
                   f' · <a href="{link}" target="_blank" rel="noopener">open in CGView</a></div>')
        if not self.client.embed:
            return (f'<div class="cgview-view" style="position:relative;{size}">{img}</div>{caption}')
        element = f"cgview-{uuid.uuid4().hex}"
        origin = self.client.view_url
        frame = (f'<iframe src="{html.escape(self.url(self._ticket()), quote=True)}" title="CGView: {alt}" '
                 f'allow="fullscreen; clipboard-write" '
                 f'style="position:absolute;left:0;top:0;width:100%;height:100%;border:0;visibility:hidden"></iframe>')
        # The viewer posts {type: "cgview-embed", ready} to its parent once it has signed in (or cannot):
        # the iframe shows then, over the picture, and stays hidden otherwise.
        script = ("<script>(function(){"
                  f"var box=document.getElementById({json.dumps(element)});"
                  "if(!box)return;var frame=box.querySelector('iframe');"
                  f"var origin={json.dumps(origin_of(origin))};"
                  "window.addEventListener('message',function(e){"
                  "if(e.source!==frame.contentWindow||e.origin!==origin||!e.data||e.data.type!=='cgview-embed')return;"
                  "frame.style.visibility=e.data.ready?'visible':'hidden';});"
                  "})();</script>")
        return (f'<div class="cgview-view" id="{element}" style="position:relative;{size}">{img}{frame}</div>'
                f"{caption}{script}")

    def _repr_mimebundle_(self, include=None, exclude=None):
        return {"text/html": self.html(), "image/png": self.png(), "text/plain": repr(self)}

    def _repr_html_(self):
        return self.html()

    def _repr_png_(self):
        return self.png()

    def __repr__(self):
        return f"<cgview View of {self.title()}: {self.url()}>"


def origin_of(url):
    """scheme://host[:port] of a URL (what a message's origin says)."""
    from urllib.parse import urlsplit
    parts = urlsplit(url)
    return f"{parts.scheme}://{parts.netloc}"


def mesh_view(client, mesh, field=None, mode=None, width=800, height=500):
    """The View of a stored mesh; field: a scalar field on it to colour it by,
    "JOB_ID/NAME", "NAME" (the newest done job on this mesh with that
    artifact, as render.png reads it), or a Job (its first scalar field)."""
    if field is None:
        return View(client, mesh, None, mode, width, height)
    if isinstance(field, dict):
        job, name = field, None
    elif isinstance(field, str) and "/" in field:
        job_id, name = field.split("/", 1)
        job = client.job(job_id)
    elif isinstance(field, str):
        name = field
        jobs = [j for j in client.jobs() if j.get("state") == "done"
                and (j.get("inputs") or {}).get("mesh") == mesh["id"] and _field_artifact(j, name)]
        if not jobs:
            raise LookupError(f"no done job on mesh {mesh['id']} has a scalar field '{name}'")
        job = max(jobs, key=lambda j: j.get("created") or "")
    else:
        raise TypeError("field: 'JOB_ID/NAME', 'NAME' or a Job")
    artifact = _field_artifact(job, name)
    if artifact is None:
        raise LookupError(f"job {job['id']} has no scalar field{' ' + repr(name) if name else ''}")
    if (job.get("inputs") or {}).get("mesh") != mesh["id"]:
        raise ValueError(f"the field of job {job['id']} is on mesh {(job.get('inputs') or {}).get('mesh')}, "
                         f"not on {mesh['id']}")
    return View(client, mesh, field_state(client, job, artifact), mode, width, height)


def job_view(client, job, artifact=None, mode=None, width=800, height=500):
    """The View of a job: its mesh coloured by its scalar field (the first, or
    `artifact`); else its skeletons drawn over its mesh and its voxel grid's
    slices open, or its output mesh in place of its input (the job's first,
    or `artifact`).  The picture is of the input mesh (render.png draws
    stored meshes and fields), and its caption says so."""
    if job.get("state") != "done":
        raise CGViewError(400, "bad_request", f"job {job['id']} is {job.get('state')}, not done: nothing to show yet")
    mesh_id = (job.get("inputs") or {}).get("mesh")
    if not isinstance(mesh_id, str):
        raise ValueError(f"job {job['id']} has no input mesh to show")
    mesh = client.mesh(mesh_id)
    field = _field_artifact(job, artifact)
    if field is not None:
        return View(client, mesh, field_state(client, job, field), mode, width, height)
    artifacts = job.get("artifacts") or []
    names = [a["name"] for a in artifacts]
    if artifact is not None and artifact not in names:
        raise LookupError(f"job {job['id']} has no artifact {artifact!r} (it has {names})")
    chosen = [a for a in artifacts if artifact in (None, a["name"])]
    key = lambda a: f"{job['id']}/{a['name']}"  # noqa: E731
    shows = [key(a) for a in chosen if a["kind"] == "skeleton"]
    shows += [key(a) for a in chosen if a["kind"] == "voxel_grid"][:1]  # one grid's slices are open at a time
    meshes = [a for a in chosen if a["kind"] == "mesh"]
    scene = None
    if meshes and not shows:
        # The output mesh stands in the scene as the viewer keeps a job's mesh (`job:JOB/ARTIFACT`), its input hidden.
        scene = [{"mesh": mesh_id, "visible": False}, {"mesh": "job:" + key(meshes[0]), "visible": True}]
    shown = [k.split("/", 1)[1] for k in shows] or ([meshes[0]["name"]] if scene else [])
    what = f"with its {', '.join(shown)}" if shown else f"its {', '.join(names) or 'results'} open from the job list"
    caption = (f"{mesh.get('name') or mesh_id}, the input of {job.get('algorithm')} {job['id']}, {what} "
               f"(the picture: the input mesh)")
    return View(client, mesh, None, mode, width, height, caption=caption, scene=scene, shows=shows)
