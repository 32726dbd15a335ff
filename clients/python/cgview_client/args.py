"""Command-line pieces that the CLI and the example scripts share."""
import argparse
import json


def connection_args():
    """A parent parser with --url, --token and --ca-file."""
    p = argparse.ArgumentParser(add_help=False)
    p.add_argument("--url", help="the server (default $CGVIEW_URL, else http://127.0.0.1:8080)")
    p.add_argument("--token", help="a bearer token (default $CGVIEW_TOKEN)")
    p.add_argument("--ca-file", help="PEM certificate(s) to trust for https:// (default $CGVIEW_CA_FILE, else the system's)")
    return p


def assignments(pairs, what):
    """{NAME: VALUE} of NAME=VALUE strings; ValueError naming a bad one."""
    out = {}
    for pair in pairs:
        name, eq, value = pair.partition("=")
        if not eq or not name:
            raise ValueError(f"{what} '{pair}' is not NAME=VALUE")
        out[name] = value
    return out


def params(pairs):
    """Algorithm parameters from NAME=VALUE strings, each VALUE as JSON when it
    parses (2, 0.5, true), else as a string."""
    out = {}
    for name, value in assignments(pairs, "parameter").items():
        try:
            out[name] = json.loads(value)
        except ValueError:
            out[name] = value
    return out


def size(text):
    """(width, height) of WIDTHxHEIGHT, for argparse's type=."""
    width, _, height = text.partition("x")
    if not (width.isdigit() and height.isdigit()):
        raise argparse.ArgumentTypeError(f"'{text}' is not WIDTHxHEIGHT")
    return int(width), int(height)
