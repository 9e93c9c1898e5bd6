"""Shared fixtures of the spinmotor Python tests (run with /usr/bin/python3 -m pytest python/tests and
the built module on PYTHONPATH, e.g. PYTHONPATH=build/python)."""
import os

import numpy as np
import pytest

import spinmotor as sm


@pytest.fixture(scope="session")
def sphere():
    """Icosphere level 2: 162 vertices, 320 faces, closed genus 0."""
    return sm.icosphere(2)


@pytest.fixture(scope="session")
def capsule():
    """Capsule along z from 0 to 3 (radius 0.5), 30 rings of 16: 482 vertices."""
    return sm.capsule(0.5, 3.0, 30, 16)


def capsule_handles(V):
    """Two disjoint handles: the bottom cap (z < -0.2) and the top cap (z > 3.2)."""
    base = np.flatnonzero(V[:, 2] < -0.2)
    tip = np.flatnonzero(V[:, 2] > 3.2)
    return [("base", base), ("tip", tip)]


@pytest.fixture(scope="session")
def meshes_dir():
    d = os.environ.get("SPINMOTOR_MESHES_DIR", "")
    if not d or not os.path.isdir(d):
        pytest.skip("../shared/meshes not found (set SPINMOTOR_MESHES_DIR)")
    return d


@pytest.fixture(scope="session")
def rigs_dir(meshes_dir):
    """../shared/rigs (next to the meshes folder); skipped when absent."""
    d = os.path.join(os.path.dirname(os.path.abspath(meshes_dir)), "rigs")
    if not os.path.isdir(d):
        pytest.skip("../shared/rigs not found")
    return d
