"""What the figure notebooks share: the client, the sample meshes, the
folder the pictures go to, and the server's renders as matplotlib images.

Environment: CGVIEW_URL (the server, as for the client), CGVIEW_SAMPLES
(the sample meshes; default build/samples of this repository) and
CGVIEW_FIGURES_DIR (where the PNGs are written; default ./figures)."""
import io
import os
import sys

import matplotlib

# Pictures go to files, with or without a display: the notebooks also run
# headless under nbclient.  Set before pyplot is imported anywhere.
matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
try:
    import cgview_client  # noqa: F401
except ImportError:
    # Run from the repository without installing the package: it is the
    # folder above this one.
    sys.path.insert(0, os.path.dirname(HERE))
from cgview_client import Client  # noqa: E402,F401 (the notebooks import it from here)

SAMPLES = os.environ.get("CGVIEW_SAMPLES") or os.path.join(HERE, "..", "..", "..", "build", "samples")
FIGURES = os.path.abspath(os.environ.get("CGVIEW_FIGURES_DIR") or "figures")


def sample(name):
    """The path of a sample mesh; FileNotFoundError saying where it looked."""
    path = os.path.join(SAMPLES, name)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"no sample {path}: set CGVIEW_SAMPLES to the folder of CGView's samples")
    return path


def picture(png, margin=6):
    """A render's PNG bytes as an RGBA float image, cropped to what is not
    background (the renderer fits the bounding box, not the silhouette)."""
    image = matplotlib.image.imread(io.BytesIO(png))
    ink = (image[..., :3].min(axis=2) < 0.98) & (image[..., 3] > 0)
    if not ink.any():
        return image
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    top, bottom = max(rows[0] - margin, 0), min(rows[-1] + margin + 1, image.shape[0])
    left, right = max(cols[0] - margin, 0), min(cols[-1] + margin + 1, image.shape[1])
    return image[top:bottom, left:right]


def show(ax, png, title=None):
    """A render in a matplotlib axes, without ticks."""
    ax.imshow(picture(png))
    ax.set_axis_off()
    if title:
        ax.set_title(title, fontsize=10)


def save(fig, name):
    """Writes the figure to FIGURES/name, closes it and shows the file in the
    notebook; its path."""
    os.makedirs(FIGURES, exist_ok=True)
    path = os.path.join(FIGURES, name)
    fig.savefig(path, dpi=110, bbox_inches="tight", facecolor="white")
    plt.close(fig)
    from cgview_client.progress import in_notebook
    if in_notebook():
        from IPython.display import Image, display
        display(Image(filename=path))
    print(path)
    return path


def grid_mesh_upload(client, job, name):
    """A job's mesh artifact (a voxel surface, say) stored as a mesh, so that
    the server can render it; the Mesh."""
    vertices, faces = job.mesh()
    return client.upload_arrays(vertices, faces, name=name)
