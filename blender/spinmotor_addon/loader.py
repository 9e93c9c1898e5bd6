"""Finds and imports the spinmotor Python module (python/ of the repository, pybind11) for the add-on.

Blender 3.4 on Debian runs the system Python 3.11, so the module built for /usr/bin/python3 imports
inside Blender once its folder (the one that contains the `spinmotor` package) is on sys.path. Searched,
in order: what Python already finds (e.g. a system-wide pip install), the folder set in the add-on's
preferences, the folders in $SPINMOTOR_PYTHONPATH (os.pathsep-separated), and the repository's
build/python when the add-on is used in place from blender/spinmotor_addon of a built checkout.
"""
import importlib
import os
import sys

ADDON_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_BUILD_DIR = os.path.normpath(os.path.join(ADDON_DIR, "..", "..", "build", "python"))


class ModuleMissing(Exception):
    """The spinmotor module could not be imported; the message says where it was looked for."""


def candidate_dirs(pref_dir=""):
    dirs = []
    if pref_dir:
        dirs.append(os.path.abspath(os.path.expanduser(pref_dir)))
    for d in os.environ.get("SPINMOTOR_PYTHONPATH", "").split(os.pathsep):
        if d:
            dirs.append(os.path.abspath(os.path.expanduser(d)))
    dirs.append(REPO_BUILD_DIR)
    return dirs


def load(pref_dir=""):
    """The spinmotor module, or ModuleMissing naming every folder tried and the import error."""
    if "spinmotor" in sys.modules:
        return sys.modules["spinmotor"]
    errors = []
    try:
        return importlib.import_module("spinmotor")
    except ImportError as e:
        errors.append(f"sys.path: {e}")
    for d in candidate_dirs(pref_dir):
        if not os.path.isdir(os.path.join(d, "spinmotor")):
            errors.append(f"{d}: no spinmotor package")
            continue
        sys.path.insert(0, d)
        try:
            return importlib.import_module("spinmotor")
        except ImportError as e:  # e.g. built for another Python: keep the real reason
            sys.path.remove(d)
            sys.modules.pop("spinmotor", None)
            errors.append(f"{d}: {e}")
    raise ModuleMissing(
        "the spinmotor Python module was not found (" + "; ".join(errors) + "). Build it (python/README.md: "
        "the CMake target spinmotor_python, or pip install --target DIR python/) and set its folder in "
        "Preferences > Add-ons > spinmotor, or $SPINMOTOR_PYTHONPATH")


_failed = {}  # pref_dir -> message: the panel redraws often, a failed search is not repeated for it


def status(pref_dir=""):
    """(ok, text) for the panel: the module's file, or why it is missing."""
    if pref_dir in _failed and "spinmotor" not in sys.modules:
        return False, _failed[pref_dir]
    try:
        sm = load(pref_dir)
        return True, f"spinmotor {getattr(sm, '__version__', '?')} ({os.path.dirname(sm.__file__)})"
    except ModuleMissing as e:
        _failed[pref_dir] = str(e)
        return False, str(e)
