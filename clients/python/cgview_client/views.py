"""Pictures of a mesh from several sides, side by side in one PNG."""
from . import png


def render_around(client, mesh_id, count=4, width=400, height=400, elevation=20, gap=0, **params):
    """The PNG bytes of `count` renders at azimuths evenly spaced around the
    mesh, left to right; params go to render.png (mode, field, projection)."""
    images = [
        png.decode(client.render(mesh_id, width=width, height=height, azimuth=f"{360 * i / count:g}",
                                 elevation=elevation, **params))
        for i in range(count)
    ]
    return png.encode(png.side_by_side(images, gap=gap))
