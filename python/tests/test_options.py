"""Every string option goes through the C++ option tables (core/option_names.hpp): option_values()
lists each table, every listed name is accepted where the option is taken, and any other string raises
spinmotor.Error naming the argument and listing every valid name."""
import re

import numpy as np
import pytest

import spinmotor as sm
from conftest import capsule_handles

# The tables the Python module exposes; a new table must be added here with a call that uses it.
KEYS = ["blend", "skin-blend", "weights", "mode", "alignment", "ffd-basis", "spline-basis", "coordinates",
        "energy", "initial", "snap-mode", "snap-alignment", "problem", "scale", "ordering", "keep",
        "cleanup", "space"]


@pytest.fixture(scope="module")
def small():
    V, F = sm.capsule(0.5, 3.0, 8, 8)
    return V, F


def two_bones():
    return [{"name": "root", "head": (0, 0, 0), "tail": (0, 0, 1.5)},
            {"name": "tip", "parent": 0, "head": (0, 0, 1.5), "tail": (0, 0, 3)}]


def bone_weights(V):
    t = np.clip((V[:, 2] - 1.0) / 1.0, 0.0, 1.0)
    return np.stack([1.0 - t, t], axis=1)


_rig = []


def rig():
    """The two-joint capsule rig of test_rig_bake.py, written once."""
    if not _rig:
        import tempfile
        from test_rig_bake import write_bent_capsule
        d = tempfile.mkdtemp()
        write_bent_capsule(d + "/bent.gltf")
        _rig.append(sm.read_gltf(d + "/bent.gltf"))
    return _rig[0]


def uses(key, V, F):
    """A callable taking one option value, passing it where `key` is used (argument name, call)."""
    h = capsule_handles(V)
    E = sm.Motor.from_rotation((1, 0, 0), 20, about=(0, 0, 2)).apply(V)
    pins = np.concatenate([ix for _, ix in h])
    cV, cF = sm.icosphere(1, radius=4.0)
    cage = (cV + [0, 0, 1.5], cF)
    table = {
        "blend": ("mode", lambda v: sm.blend([sm.Motor(), sm.Motor.from_translation((0, 0, 1))], [0.5, 0.5],
                                              mode=v)),
        "skin-blend": ("blend", lambda v: sm.SkinDeformer(V, F, skeleton=two_bones(), weights=bone_weights(V),
                                                          blend=v)),
        "weights": ("weights", lambda v: sm.SurfaceHarmonicDeformer(V, F, handles=h, weights=v)),
        "mode": ("mode", lambda v: sm.FfdDeformer(V, F, lattice=(2, 2, 2), mode=v)),
        "alignment": ("alignment", lambda v: sm.metrics(V, E, F, alignment=v)),
        "ffd-basis": ("basis", lambda v: sm.FfdDeformer(V, F, lattice=(3, 3, 3), basis=v)),
        "spline-basis": ("basis", lambda v: sm.SplineDeformer(V, F, handles=h, basis=v,
                                                             keys=3 if v == "quadratic" else 4)),
        "coordinates": ("coordinates", lambda v: sm.CageDeformer(V, F, cage=cage, coordinates=v, grid=8)),
        "energy": ("energy", lambda v: sm.ArapDeformer(V, F, handles=h, energy=v)),
        "initial": ("initial", lambda v: sm.ArapDeformer(V, F, handles=h, initial=v)),
        "snap-mode": ("mode", lambda v: sm.ConformalSnap(V, F).snap(E, mode=v, **({"pins": pins} if v == "pinned"
                                                                                 else {}))),
        "snap-alignment": ("alignment", lambda v: sm.ConformalSnap(V, F, alignment=v)),
        "problem": ("problem", lambda v: sm.SpinTransform(V, F, problem=v)),
        "scale": ("scale", lambda v: sm.SpinTransform(V, F, scale=v)),
        "ordering": ("ordering", lambda v: sm.SpinTransform(V, F, ordering=v)),
        "keep": ("keep", lambda v: sm.PinnedCleanup(V, F, pins, keep=v)),
        "cleanup": ("cleanup", lambda v: rig().poser(cleanup=v)),
        "space": ("space", lambda v: rig().poser(space=v)),
    }
    return table[key]


def test_option_values_lists_every_table():
    allv = sm.option_values()
    assert list(allv) == KEYS
    for k in KEYS:
        assert sm.option_values(k) == allv[k] and len(allv[k]) >= 2, k
    assert sm.option_values("snap-mode") == ["free", "spin", "shape", "pinned"]
    assert sm.option_values("keep") == ["auto", "volume", "area", "none"]
    assert sm.option_values("problem") == ["standard", "generalized", "unweighted"]
    assert sm.option_values("snap-alignment") == ["similarity", "translation", "none"]
    with pytest.raises(sm.Error, match="unknown option 'colour'.*snap-mode"):
        sm.option_values("colour")


@pytest.mark.parametrize("key", KEYS)
def test_names_accepted_and_bad_names_listed(key, small):
    V, F = small
    arg, call = uses(key, V, F)
    names = sm.option_values(key)
    for name in names:
        call(name)  # no error
    with pytest.raises(sm.Error) as e:
        call("no-such-" + key)
    msg = str(e.value)
    assert msg.startswith(arg + ":"), msg  # names the argument
    assert "'no-such-" + key + "'" in msg
    listed = re.search(r"\(one of: (.*)\)", msg).group(1).split(", ")
    assert listed == names, msg  # lists exactly the table
    assert e.value.kind == "bad_input"
    with pytest.raises(sm.Error):
        call("")


def test_unweighted_snap_is_refused_with_the_reason(small):
    """The snap takes the problem table's names but only standard and generalized make sense there."""
    V, F = small
    with pytest.raises(sm.Error, match="standard .* or generalized"):
        sm.ConformalSnap(V, F, problem="unweighted")


def test_snap_options_belong_to_their_mode(small):
    V, F = small
    E = V * [1.0, 1.0, 1.1]
    snap = sm.ConformalSnap(V, F)
    with pytest.raises(sm.Error, match='tradeoff: belongs to mode "free", not "pinned"'):
        snap.snap(E, pins=[0], tradeoff=0.5)
    with pytest.raises(sm.Error, match='pins: belongs to mode "pinned", not "shape"'):
        snap.snap(E, mode="shape", pins=[0])
    with pytest.raises(sm.Error, match='steps: belongs to mode "shape", not "free"'):
        snap.snap(E, steps=3)
    with pytest.raises(sm.Error, match='keep: belongs to mode "pinned"'):
        snap.snap(E, keep="area")
    with pytest.raises(sm.Error, match="pins: mode \"pinned\" needs"):
        snap.snap(E, mode="pinned")
    with pytest.raises(sm.Error, match="mode: expected a str"):
        snap.snap(E, mode=3)
    with pytest.raises(sm.Error, match="tradeoff: expected a number"):
        snap.snap(E, tradeoff="half")
    # "spin" is the former name of "free"
    assert np.array_equal(snap.snap(E, mode="spin"), snap.snap(E, mode="free"))
