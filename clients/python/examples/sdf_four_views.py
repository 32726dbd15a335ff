#!/usr/bin/env python3
"""The paper's SDF figure: a mesh coloured by its Shape Diameter Function,
seen from four sides, in one PNG.

    python3 clients/python/examples/sdf_four_views.py elephant.off -o elephant-sdf.png
    python3 clients/python/examples/sdf_four_views.py bunny.ply --algorithm curvature --artifact mean_curvature

MESH is a mesh id or name on the server (the sample meshes are there when it
runs with --samples default), or a file to upload.  The job runs (with a
progress bar), then render.png colours the mesh by the job's artifact from
azimuths 0, 90, 180 and 270 degrees, and the four pictures are put side by
side.  Another scalar-field algorithm: --algorithm and --artifact.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from cgview_client import CGViewError, Client, JobFailed, ProgressBar, args, render_around  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], parents=[args.connection_args()])
    p.add_argument("mesh", nargs="?", default="elephant.off", help="id, name or file (default elephant.off)")
    p.add_argument("--algorithm", default="sdf", help="the algorithm to run (default sdf)")
    p.add_argument("--artifact", default="sdf", help="its scalar field to colour by (default sdf)")
    p.add_argument("-p", "--param", action="append", default=[], metavar="NAME=VALUE", help="a parameter; repeatable")
    p.add_argument("--size", type=args.size, default=(400, 400), metavar="WxH", help="of one view (default 400x400)")
    p.add_argument("--elevation", type=float, default=20, help="degrees above the horizon (default 20)")
    p.add_argument("--mode", default="smooth", help="shading: flat, smooth (default) or toon")
    p.add_argument("-o", "--output", help="the PNG (default MESH-ARTIFACT.png)")
    a = p.parse_args(argv)
    client = Client(a.url, a.token, ca_file=a.ca_file)
    try:
        mesh = client.find_mesh(a.mesh)
        job = client.run(a.algorithm, mesh["id"], args.params(a.param), on_progress=ProgressBar())
        if a.artifact not in [x["name"] for x in job["artifacts"]]:
            names = ", ".join(x["name"] for x in job["artifacts"])
            raise LookupError(f"{a.algorithm} gave no artifact '{a.artifact}' (it gave {names})")
        width, height = a.size
        figure = render_around(client, mesh["id"], 4, width, height, a.elevation, mode=a.mode,
                               field=f"{job['id']}/{a.artifact}")
    except (CGViewError, JobFailed, LookupError, OSError, ValueError) as e:
        print(f"{p.prog}: error: {e}", file=sys.stderr)
        return 1
    output = a.output or f"{os.path.splitext(mesh['name'])[0]}-{a.artifact}.png"
    with open(output, "wb") as f:
        f.write(figure)
    print(output)
    return 0


if __name__ == "__main__":
    sys.exit(main())
