"""The package's build backend (PEP 517 and PEP 660), in the standard library alone.

pip builds a package in an isolated environment and fetches the build
backend named in pyproject.toml (setuptools, wheel) into it from a package
index; a lab machine with no index has none to fetch from, and a system's
setuptools (Debian's python3-setuptools) breaks under another Python
(pyenv's, conda's).  The client is pure Python, so this backend writes its
wheel itself, with zipfile: the files of the packages that pyproject.toml
names, and the .dist-info (METADATA, WHEEL, entry_points.txt, RECORD) from
its [project] table.  `requires = []`: pip needs nothing from an index, in
a venv of any Python 3.9 or newer.

It reads pyproject.toml with tomllib (Python 3.11 and newer) or, before
3.11, with the small TOML reader below (strings, arrays, inline tables,
booleans, integers, [tables]: what pyproject.toml uses)."""
import base64
import gzip
import hashlib
import io
import os
import re
import tarfile
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# A fixed time for the archives' entries, so that two builds give the same bytes.
EPOCH = (1980, 1, 1, 0, 0, 0)
WHEEL = "Wheel-Version: 1.0\nGenerator: cgview-client _build/backend.py\nRoot-Is-Purelib: true\nTag: py3-none-any\n"


# --- pyproject.toml ----------------------------------------------------------------

class TomlError(ValueError):
    pass


class _Toml:
    """Just enough TOML for a pyproject.toml: [table] and [a.b] headers,
    bare, quoted and dotted keys, "basic" and 'literal' strings (one line),
    arrays over several lines, inline tables, true/false, integers, comments."""
    _ESCAPES = {"b": "\b", "t": "\t", "n": "\n", "f": "\f", "r": "\r", '"': '"', "\\": "\\"}

    def __init__(self, text):
        self.s, self.i = text, 0

    def error(self, what):
        line = self.s.count("\n", 0, self.i) + 1
        raise TomlError(f"pyproject.toml, line {line}: {what}")

    def skip(self, newlines):
        while self.i < len(self.s):
            c = self.s[self.i]
            if c in " \t\r" or (newlines and c == "\n"):
                self.i += 1
            elif c == "#":
                end = self.s.find("\n", self.i)
                self.i = len(self.s) if end < 0 else end
            else:
                break

    def peek(self):
        return self.s[self.i] if self.i < len(self.s) else ""

    def expect(self, c):
        if self.peek() != c:
            self.error(f"expected {c!r}")
        self.i += 1

    def string(self):
        quote = self.peek()
        self.i += 1
        out = []
        while True:
            c = self.peek()
            if c in ("", "\n"):
                self.error("unterminated string")
            self.i += 1
            if c == quote:
                return "".join(out)
            if c == "\\" and quote == '"':
                e = self.peek()
                self.i += 1
                if e in self._ESCAPES:
                    out.append(self._ESCAPES[e])
                elif e in "uU":
                    n = 4 if e == "u" else 8
                    out.append(chr(int(self.s[self.i:self.i + n], 16)))
                    self.i += n
                else:
                    self.error(f"unknown escape \\{e}")
            else:
                out.append(c)

    def key(self):
        parts = []
        while True:
            self.skip(False)
            if self.peek() in ('"', "'"):
                parts.append(self.string())
            else:
                m = re.compile(r"[A-Za-z0-9_-]+").match(self.s, self.i)
                if not m:
                    self.error("expected a key")
                parts.append(m.group())
                self.i = m.end()
            self.skip(False)
            if self.peek() != ".":
                return parts
            self.i += 1

    def value(self):
        c = self.peek()
        if c in ('"', "'"):
            if self.s.startswith(c * 3, self.i):
                self.error("multi-line strings are not read here")
            return self.string()
        if c == "[":
            self.i += 1
            items = []
            while True:
                self.skip(True)
                if self.peek() == "]":
                    self.i += 1
                    return items
                items.append(self.value())
                self.skip(True)
                if self.peek() == ",":
                    self.i += 1
                elif self.peek() != "]":
                    self.error("expected ',' or ']'")
        if c == "{":
            self.i += 1
            table = {}
            self.skip(False)
            if self.peek() == "}":
                self.i += 1
                return table
            while True:
                self.assign(table)
                self.skip(False)
                if self.peek() == "}":
                    self.i += 1
                    return table
                self.expect(",")
        m = re.compile(r"true|false|[+-]?[0-9][0-9_]*").match(self.s, self.i)
        if not m:
            self.error("expected a value")
        self.i = m.end()
        word = m.group()
        return word == "true" if word in ("true", "false") else int(word.replace("_", ""))

    def assign(self, table):
        keys = self.key()
        self.expect("=")
        self.skip(False)
        for k in keys[:-1]:
            table = table.setdefault(k, {})
        if keys[-1] in table:
            self.error(f"{keys[-1]} is given twice")
        table[keys[-1]] = self.value()

    def document(self):
        root = table = {}
        while True:
            self.skip(True)
            if self.i >= len(self.s):
                return root
            if self.peek() == "[":
                self.i += 1
                if self.peek() == "[":
                    self.error("arrays of tables are not read here")
                keys = self.key()
                self.expect("]")
                table = root
                for k in keys:
                    table = table.setdefault(k, {})
            else:
                self.assign(table)
            self.skip(False)
            if self.peek() not in ("", "\n"):
                self.error("expected the end of the line")


def parse_toml(text):
    return _Toml(text).document()


def pyproject():
    with open(os.path.join(ROOT, "pyproject.toml"), encoding="utf-8") as f:
        text = f.read()
    try:
        import tomllib
    except ImportError:
        return parse_toml(text)
    return tomllib.loads(text)


# --- what goes into the wheel ------------------------------------------------------

class Project:
    def __init__(self):
        doc = pyproject()
        self.meta = doc["project"]
        self.name = self.meta["name"]
        self.version = self.meta["version"]
        # The distribution's name in file names (PEP 427, PEP 503).
        self.dist = re.sub(r"[-_.]+", "_", self.name).lower()
        self.dist_info = f"{self.dist}-{self.version}.dist-info"
        self.packages = doc.get("tool", {}).get("cgview-build", {}).get("packages", [self.dist])

    def readme(self):
        readme = self.meta.get("readme")
        if readme is None:
            return None, None
        if isinstance(readme, dict):
            path, content_type = readme.get("file"), readme.get("content-type")
        else:
            path, content_type = readme, None
        if content_type is None:
            content_type = {".md": "text/markdown", ".rst": "text/x-rst"}.get(os.path.splitext(path)[1], "text/plain")
        with open(os.path.join(ROOT, path), encoding="utf-8") as f:
            return f.read(), content_type

    def metadata(self):
        m = self.meta
        lines = ["Metadata-Version: 2.1", f"Name: {self.name}", f"Version: {self.version}"]
        if "description" in m:
            lines.append(f"Summary: {m['description']}")
        license = m.get("license")
        if isinstance(license, dict) and "text" in license:
            lines.append(f"License: {license['text']}")
        if "requires-python" in m:
            lines.append(f"Requires-Python: {m['requires-python']}")
        lines += [f"Requires-Dist: {d}" for d in m.get("dependencies", [])]
        for extra, deps in m.get("optional-dependencies", {}).items():
            lines.append(f"Provides-Extra: {extra}")
            lines += [f'Requires-Dist: {d}; extra == "{extra}"' for d in deps]
        text, content_type = self.readme()
        if text is not None:
            lines.append(f"Description-Content-Type: {content_type}")
        return "\n".join(lines) + "\n" + ("\n" + text if text is not None else "")

    def entry_points(self):
        m = self.meta
        groups = {"console_scripts": m.get("scripts", {}), "gui_scripts": m.get("gui-scripts", {}),
                  **m.get("entry-points", {})}
        out = ""
        for group, points in groups.items():
            if points:
                out += f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in points.items()) + "\n"
        return out

    def dist_info_files(self):
        files = {"METADATA": self.metadata(), "WHEEL": WHEEL}
        entry_points = self.entry_points()
        if entry_points:
            files["entry_points.txt"] = entry_points
        return {name: text.encode("utf-8") for name, text in files.items()}

    def package_files(self):
        """(path in the archive, path on disk) of every file of the packages, sorted."""
        out = []
        for package in self.packages:
            top = os.path.join(ROOT, *package.split("."))
            if not os.path.isfile(os.path.join(top, "__init__.py")):
                raise FileNotFoundError(f"package {package}: no {top}/__init__.py")
            for directory, dirs, names in os.walk(top):
                dirs[:] = sorted(d for d in dirs if d != "__pycache__" and not d.startswith("."))
                for name in sorted(names):
                    if name.endswith((".pyc", ".pyo")) or name.startswith("."):
                        continue
                    path = os.path.join(directory, name)
                    out.append((os.path.relpath(path, ROOT).replace(os.sep, "/"), path))
        return sorted(out)


def _zip_entry(z, name, data):
    info = zipfile.ZipInfo(name, EPOCH)
    info.external_attr = 0o644 << 16
    info.compress_type = zipfile.ZIP_DEFLATED
    z.writestr(info, data)


def _write_wheel(wheel_directory, project, contents):
    """A wheel of `contents` ([(name, bytes)]) and the project's .dist-info, RECORD last."""
    filename = f"{project.dist}-{project.version}-py3-none-any.whl"
    entries = list(contents) + [(f"{project.dist_info}/{n}", d) for n, d in project.dist_info_files().items()]
    record = []
    with zipfile.ZipFile(os.path.join(wheel_directory, filename), "w") as z:
        for name, data in entries:
            _zip_entry(z, name, data)
            digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
            record.append(f"{name},sha256={digest},{len(data)}")
        record.append(f"{project.dist_info}/RECORD,,")
        _zip_entry(z, f"{project.dist_info}/RECORD", ("\n".join(record) + "\n").encode("utf-8"))
    return filename


def _read(path):
    with open(path, "rb") as f:
        return f.read()


# --- PEP 517 -------------------------------------------------------------------------

def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def get_requires_for_build_editable(config_settings=None):
    return []


def prepare_metadata_for_build_wheel(metadata_directory, config_settings=None):
    project = Project()
    target = os.path.join(metadata_directory, project.dist_info)
    os.makedirs(target, exist_ok=True)
    for name, data in project.dist_info_files().items():
        with open(os.path.join(target, name), "wb") as f:
            f.write(data)
    return project.dist_info


prepare_metadata_for_build_editable = prepare_metadata_for_build_wheel


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    project = Project()
    return _write_wheel(wheel_directory, project, [(name, _read(path)) for name, path in project.package_files()])


def build_editable(wheel_directory, config_settings=None, metadata_directory=None):
    """PEP 660: a wheel whose .pth puts this folder on sys.path, so that the
    installed package is the source tree itself."""
    project = Project()
    pth = f"__editable__.{project.dist}-{project.version}.pth"
    return _write_wheel(wheel_directory, project, [(pth, (ROOT + "\n").encode("utf-8"))])


def build_sdist(sdist_directory, config_settings=None):
    project = Project()
    base = f"{project.dist}-{project.version}"
    files = [("pyproject.toml", os.path.join(ROOT, "pyproject.toml")),
             ("_build/backend.py", os.path.abspath(__file__))] + project.package_files()
    readme = project.meta.get("readme")
    readme = readme.get("file") if isinstance(readme, dict) else readme
    if readme:
        files.append((readme.replace(os.sep, "/"), os.path.join(ROOT, readme)))
    entries = [(name, _read(path)) for name, path in sorted(set(files))]
    entries.append(("PKG-INFO", project.metadata().encode("utf-8")))
    filename = base + ".tar.gz"
    with open(os.path.join(sdist_directory, filename), "wb") as f, \
            gzip.GzipFile(fileobj=f, mode="wb", mtime=0) as gz, \
            tarfile.open(fileobj=gz, mode="w", format=tarfile.PAX_FORMAT) as tar:
        for name, data in entries:
            info = tarfile.TarInfo(f"{base}/{name}")
            info.size, info.mode, info.mtime = len(data), 0o644, 315532800
            tar.addfile(info, io.BytesIO(data))
    return filename
