"""An algorithm's parameters checked against its JSON Schema (from GET
/api/v1/algorithms) before a job is sent: a misspelt name or a value out of
range raises at once, naming the closest known name or the range."""
import difflib
import json

from .errors import CGViewError


class ParameterError(CGViewError, ValueError):
    """A parameter the algorithm does not take, or a value it refuses, found
    before anything is sent: the 400 bad_request the server would answer,
    in its words; .parameter names it."""

    def __init__(self, detail, parameter):
        super().__init__(400, "bad_request", detail, parameter)


def _num(x):
    return str(int(x)) if isinstance(x, float) and x.is_integer() else json.dumps(x)


def check(algorithm, given):
    """Raises ParameterError for the first bad parameter of `given` (a dict)."""
    props = algorithm.get("params", {}).get("properties", {})
    name_of = algorithm["name"]
    for name, value in given.items():
        if name not in props:
            close = difflib.get_close_matches(name, list(props), n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else f" (it takes: {', '.join(props) or 'none'})"
            raise ParameterError(f"algorithm '{name_of}' has no parameter '{name}'{hint}", name)
        p = props[name]
        kind = p.get("type")
        ok = {"integer": isinstance(value, int) and not isinstance(value, bool),
              "number": isinstance(value, (int, float)) and not isinstance(value, bool),
              "boolean": isinstance(value, bool),
              "string": isinstance(value, str),
              "array": isinstance(value, (list, tuple))}.get(kind, True)
        if not ok:
            raise ParameterError(f"parameter '{name}': must be a {kind}, got {json.dumps(value)}", name)
        if "enum" in p and value not in p["enum"]:
            raise ParameterError(f"parameter '{name}': {json.dumps(value)} is not one of {', '.join(map(str, p['enum']))}", name)
        if kind in ("integer", "number"):
            if "minimum" in p and value < p["minimum"]:
                raise ParameterError(f"parameter '{name}': {_num(value)} is under the minimum {_num(p['minimum'])}", name)
            if "maximum" in p and value > p["maximum"]:
                raise ParameterError(f"parameter '{name}': {_num(value)} is over the maximum {_num(p['maximum'])}", name)


def describe(algorithm):
    """A docstring: what the algorithm does, its inputs and each parameter's
    type, range or choices, default and meaning."""
    lines = [f"{algorithm.get('title', algorithm['name'])}: {algorithm.get('description', '')}".rstrip(": "), ""]
    inputs = algorithm.get("inputs") or [{"name": "mesh", "kind": "mesh"}]
    lines.append("Inputs: " + ", ".join(f"{i['name']} ({i.get('kind', 'mesh')})" for i in inputs))
    props = algorithm.get("params", {}).get("properties", {})
    if props:
        lines += ["", "Parameters:"]
    for name, p in props.items():
        rule = (f"one of {p['enum']}" if "enum" in p else
                f"{_num(p['minimum']) if 'minimum' in p else ''}..{_num(p['maximum']) if 'maximum' in p else ''}"
                if "minimum" in p or "maximum" in p else "")
        default = f", default {p['default']!r}" if "default" in p else ""
        lines.append(f"  {name} ({p.get('type', 'any')}{', ' + rule if rule else ''}{default}): "
                     f"{p.get('title', '')}{' - ' + p['description'] if p.get('description') else ''}")
    outputs = algorithm.get("outputs") or []
    if outputs:
        lines += ["", "Outputs: " + ", ".join(f"{o['name']} ({o['kind']})" for o in outputs)]
    return "\n".join(lines)
