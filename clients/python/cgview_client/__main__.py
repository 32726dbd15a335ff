"""python3 -m cgview_client COMMAND ...: the CGView server from a shell.
Every command takes --url (default $CGVIEW_URL or http://127.0.0.1:8080) and
--token (default $CGVIEW_TOKEN)."""
import argparse
import json
import sys

from . import args
from .client import CGViewError, Client, JobFailed
from .progress import ProgressBar
from .views import render_around


def main(argv=None):
    options = parser().parse_args(argv)
    client = Client(options.url, options.token, ca_file=options.ca_file)
    try:
        return options.command(client, options) or 0
    except (CGViewError, JobFailed, LookupError, OSError, TimeoutError, ValueError) as e:
        print(f"cgview_client: error: {e}", file=sys.stderr)
        return 1


def parser():
    p = argparse.ArgumentParser(prog="python3 -m cgview_client", description=__doc__.split("\n")[0])
    common = args.connection_args()
    sub = p.add_subparsers(required=True, metavar="COMMAND")

    def command(name, function, help):
        c = sub.add_parser(name, parents=[common], help=help, description=help)
        c.set_defaults(command=function)
        return c

    c = command("health", lambda client, a: print_json(client.health()), "the server's health")
    c = command("upload", upload, "upload a mesh file; prints its id")
    c.add_argument("file")
    c.add_argument("--name", help="its name on the server (default: the file's name)")
    c.add_argument("--json", action="store_true", help="print the whole Mesh object")
    c = command("list", list_things, "list meshes (default), jobs or algorithms")
    c.add_argument("what", nargs="?", choices=["meshes", "jobs", "algorithms"], default="meshes")
    c.add_argument("--json", action="store_true", help="print the JSON objects")
    c = command("run", run, "run an algorithm on a mesh with a progress bar; prints the job id")
    c.add_argument("algorithm")
    c.add_argument("mesh", help="a mesh id or name on the server, or a file to upload")
    c.add_argument("-p", "--param", action="append", default=[], metavar="NAME=VALUE",
                   help="a parameter (VALUE as JSON when it parses, else a string); repeatable")
    c.add_argument("-i", "--input", action="append", default=[], metavar="NAME=MESH",
                   help="another input mesh (hausdorff's reference); repeatable")
    c.add_argument("--no-wait", action="store_true", help="submit only")
    c.add_argument("-o", "--output", metavar="DIR", help="then download its artifacts into DIR")
    c = command("wait", wait, "wait for a job with a progress bar; fails unless it ends done")
    c.add_argument("job")
    c.add_argument("--timeout", type=float, help="seconds")
    c = command("download", download, "download a job's artifacts (all, or those named)")
    c.add_argument("job")
    c.add_argument("names", nargs="*", metavar="ARTIFACT")
    c.add_argument("-o", "--output", default=".", metavar="DIR", help="where (default .)")
    c.add_argument("--format", help="e.g. json, csv, txt, ply, f32 (default: the artifact's own)")
    c = command("render", render, "a PNG of a mesh; several views side by side with --views")
    c.add_argument("mesh", help="a mesh id or name on the server, or a file to upload")
    c.add_argument("-o", "--output", required=True, metavar="FILE.png")
    c.add_argument("--mode", help="points, wireframe, flat, smooth (default), toon")
    c.add_argument("--size", type=args.size, default=(800, 600), metavar="WxH", help="of one view (default 800x600)")
    c.add_argument("--azimuth", type=float, help="degrees (default 30; --views N: 0, 360/N, ...)")
    c.add_argument("--elevation", type=float, default=20, help="degrees (default 20)")
    c.add_argument("--projection", choices=["perspective", "orthographic"])
    c.add_argument("--field", help="a scalar field to colour by: JOB/ARTIFACT, or ARTIFACT of the newest job")
    c.add_argument("--views", type=int, default=1, help="views evenly around the mesh, side by side")
    return p


def print_json(value):
    print(json.dumps(value, indent=2))


def upload(client, a):
    mesh = client.upload(a.file, a.name)
    print_json(mesh) if a.json else print(mesh["id"])


def list_things(client, a):
    items = getattr(client, a.what)()
    if a.json:
        return print_json(items)
    for x in items:
        if a.what == "meshes":
            r = x.get("report", {})
            print(f"{x['id']}  {x['name']:<28} {r.get('vertices', '?'):>8} vertices {r.get('faces', '?'):>8} faces")
        elif a.what == "jobs":
            print(f"{x['id']}  {x['algorithm']:<20} {x['state']:<11} {x['progress']:4.0%}  {x.get('error') or ''}")
        else:
            print(f"{x['name']:<22} {x['title']}")


def run(client, a):
    params = args.params(a.param)
    inputs = {k: client.find_mesh(v)["id"] for k, v in args.assignments(a.input, "input").items()}
    job = client.submit(a.algorithm, client.find_mesh(a.mesh)["id"], params, inputs)
    print(job["id"])
    sys.stdout.flush()
    if a.no_wait:
        return 0
    status = wait_for(client, job["id"])
    if status == 0 and a.output:
        for path in client.download(job["id"], a.output):
            print(path)
    return status


def wait(client, a):
    return wait_for(client, a.job, a.timeout)


def wait_for(client, job_id, timeout=None):
    job = client.wait(job_id, ProgressBar(), timeout)
    if job["state"] != "done":
        raise JobFailed(job)
    return 0


def download(client, a):
    for path in client.download(a.job, a.output, a.names or None, a.format):
        print(path)


def render(client, a):
    width, height = a.size
    mesh_id = client.find_mesh(a.mesh)["id"]
    params = {"mode": a.mode, "projection": a.projection, "field": a.field}
    if a.views > 1:
        data = render_around(client, mesh_id, a.views, width, height, a.elevation, **params)
    else:
        data = client.render(mesh_id, width=width, height=height, azimuth=a.azimuth, elevation=a.elevation, **params)
    with open(a.output, "wb") as f:
        f.write(data)
    print(a.output)


if __name__ == "__main__":
    sys.exit(main())
