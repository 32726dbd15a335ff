"""`pip install --no-index ./clients/python`, as the README says, into a fresh
venv of each Python 3.9 or newer found here: the `python3` first on the
PATH (pyenv's, conda's), Debian's /usr/bin/python3 and pyenv's oldest and
newest versions.
No package index and no --no-build-isolation: the build backend
(_build/backend.py) is the standard library alone.  Each venv then imports
cgview_client from its site-packages, reports the version of pyproject.toml
and runs the cgview-client command; one install is editable (-e).

Its own CTest test (python_client.pip_install), not in the unittest discover
patterns of python_client.1-3: no server needed, the venvs side by side."""
import concurrent.futures
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

CLIENT_DIR = os.path.abspath(os.path.join(os.path.dirname(__file__), ".."))
sys.path.insert(0, os.path.join(CLIENT_DIR, "_build"))
import backend  # noqa: E402  (the package's build backend, _build/backend.py)

VERSION = backend.Project().version
ENV = {**os.environ, "PIP_NO_INDEX": "1", "PIP_DISABLE_PIP_VERSION_CHECK": "1", "PYTHONDONTWRITEBYTECODE": "1",
       "PYTHONPATH": "", "PIP_NO_INPUT": "1"}
ENV.pop("PIP_INDEX_URL", None)
ENV.pop("PIP_FIND_LINKS", None)


def interpreters():
    """{real path of a Python 3.9+ with venv and ensurepip: how it was found}:
    python3 on the PATH, /usr/bin/python3, and of pyenv's other versions the
    oldest and the newest (3.9 reads pyproject.toml without tomllib), to keep
    the test short."""
    found = {}
    candidates = [(shutil.which("python3"), "python3 on the PATH"), ("/usr/bin/python3", "Debian's /usr/bin/python3")]
    root = os.environ.get("PYENV_ROOT") or os.path.expanduser("~/.pyenv")
    pyenv = []
    for path in glob.glob(os.path.join(root, "versions", "*", "bin", "python3")):
        name = path.split(os.sep)[-3]
        try:
            version = tuple(int(x) for x in name.split("."))
        except ValueError:  # a virtualenv or a conda of pyenv's
            continue
        if version >= (3, 9):
            pyenv.append((version, path, "pyenv " + name))
    pyenv.sort()
    candidates += [(path, how) for _, path, how in pyenv[:1] + pyenv[-1:]]
    for path, how in candidates:
        if not path or not os.path.exists(path):
            continue
        # A pyenv shim names the real interpreter only when it runs.
        p = subprocess.run([path, "-c", "import sys, venv, ensurepip; print(sys.executable); "
                                        "print(sys.version_info >= (3, 9))"],
                           capture_output=True, text=True, env=ENV, timeout=30)
        lines = p.stdout.split()
        if p.returncode != 0 or len(lines) != 2 or lines[1] != "True":
            continue
        found.setdefault(os.path.realpath(lines[0]), how)
    return found


def install_and_check(python, how, directory, editable):
    """Errors of a venv made by `python` with the client installed in it: '' when none."""
    venv = os.path.join(directory, "venv")
    bin_dir = os.path.join(venv, "bin")
    steps = [
        [python, "-m", "venv", venv],
        [os.path.join(bin_dir, "pip"), "install", "--no-index"] + (["-e"] if editable else []) + [CLIENT_DIR],
        [os.path.join(bin_dir, "python"), "-c",
         "import cgview_client, importlib.metadata, os, sys\n"
         "print(sys.version.split()[0], importlib.metadata.version('cgview-client'), "
         "os.path.realpath(cgview_client.__file__))"],
        [os.path.join(bin_dir, "cgview-client"), "--help"],
    ]
    outputs = []
    for argv in steps:
        p = subprocess.run(argv, capture_output=True, text=True, env=ENV, cwd=directory, timeout=120)
        if p.returncode != 0:
            return f"{how} ({python}): `{' '.join(argv)}` exited {p.returncode}:\n{p.stdout}{p.stderr}"
        outputs.append(p.stdout)
    words = outputs[2].split()
    expected = os.path.realpath(os.path.join(CLIENT_DIR if editable else venv, "")) + os.sep
    if len(words) != 3 or words[1] != VERSION or not words[2].startswith(expected):
        return f"{how} ({python}): expected version {VERSION} imported from {expected}, got: {outputs[2]}"
    if "cgview_client" not in outputs[3]:
        return f"{how} ({python}): cgview-client --help: {outputs[3]}"
    return ""


class PipInstallTest(unittest.TestCase):
    def test_the_toml_reader_before_311_reads_pyproject_as_tomllib_does(self):
        try:
            import tomllib
        except ImportError:
            self.skipTest("no tomllib before Python 3.11")
        with open(os.path.join(CLIENT_DIR, "pyproject.toml"), encoding="utf-8") as f:
            text = f.read()
        self.assertEqual(backend.parse_toml(text), tomllib.loads(text))
        sample = 'a = "x\\u00e9\\"" # c\n[t.u]\n"k.q" = [1, [true, false],\n  {x = \'lit\\\\\'},\n]\nd.e = -2\n'
        self.assertEqual(backend.parse_toml(sample), tomllib.loads(sample))

    def test_pip_installs_it_in_a_venv_of_each_python(self):
        found = interpreters()
        self.assertTrue(found, "no Python 3.9 or newer with venv and ensurepip")
        print("interpreters:", ", ".join(f"{how} = {path}" for path, how in found.items()), file=sys.stderr)
        before = sorted(os.listdir(CLIENT_DIR)), sorted(os.listdir(os.path.join(CLIENT_DIR, "_build")))
        with tempfile.TemporaryDirectory(prefix="cgview-pip-") as tmp:
            jobs = [(path, how, False) for path, how in found.items()]
            # One editable install, with the first one found (python3 on the PATH).
            jobs.append((next(iter(found)), next(iter(found.values())) + ", editable", True))
            with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
                futures = []
                for k, (path, how, editable) in enumerate(jobs):
                    directory = os.path.join(tmp, str(k))
                    os.mkdir(directory)
                    futures.append(pool.submit(install_and_check, path, how, directory, editable))
                errors = [f.result() for f in futures]
        self.assertEqual([e for e in errors if e], [])
        # The build leaves nothing in the source tree (no build/, no .egg-info).
        self.assertEqual(before, (sorted(os.listdir(CLIENT_DIR)), sorted(os.listdir(os.path.join(CLIENT_DIR, "_build")))))


if __name__ == "__main__":
    unittest.main()
