"""The package's build backend: setuptools, found where the system keeps it.

pip builds a package in an isolated environment and fetches the build
backend (setuptools) into it from a package index; a lab machine with
Debian's packages and no index has none to fetch from.  This backend,
which needs nothing fetched, hands every call to the setuptools the
system has (Debian's python3-setuptools)."""
import site
import sys
import sysconfig

try:
    import setuptools  # noqa: F401  (a venv or an index provided it)
except ImportError:
    for directory in ["/usr/lib/python3/dist-packages", *site.getsitepackages(), sysconfig.get_paths()["purelib"]]:
        if directory not in sys.path:
            sys.path.append(directory)

from setuptools.build_meta import *  # noqa: E402,F401,F403


# setuptools asks for `wheel` to be fetched; the system's (Debian's
# python3-wheel) is found the same way as setuptools itself.
def get_requires_for_build_wheel(config_settings=None):
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []


def get_requires_for_build_editable(config_settings=None):
    return []
