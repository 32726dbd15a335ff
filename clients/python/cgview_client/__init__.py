"""A client of the CGView server (protocol/API.md) in Python's standard
library; Debian's python3-websocket, when installed, gives live job progress.

    from cgview_client import Client, ProgressBar
    c = Client("http://127.0.0.1:8080", token=None)   # or $CGVIEW_URL, $CGVIEW_TOKEN
    mesh = c.upload("bunny.ply")
    job = c.run("curvature", mesh["id"], on_progress=ProgressBar())
    c.download(job["id"], "results/")
    open("bunny.png", "wb").write(c.render(mesh["id"], field=f"{job['id']}/mean_curvature"))
"""
from .client import DEFAULT_URL, Client
from .errors import CGViewError, JobFailed
from .objects import Job, Mesh
from .params import ParameterError
from . import args
from .progress import NotebookProgressBar, ProgressBar
from .views import render_around

__all__ = ["Client", "CGViewError", "JobFailed", "Job", "Mesh", "ParameterError", "ProgressBar", "NotebookProgressBar",
           "DEFAULT_URL", "render_around"]
