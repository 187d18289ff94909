"""Every object pickles and gives the same answers after the round trip."""

from __future__ import annotations

import pickle

import numpy as np

import stance


def round_trip(x):  # type: ignore[no-untyped-def]
    return pickle.loads(pickle.dumps(x))


def test_inputs_round_trip() -> None:
    st = stance.Stance.from_scene("box-climbing")
    st2 = round_trip(st)
    assert st2.to_dict() == st.to_dict()
    assert np.array_equal(st2.giwc().facets, st.giwc().facets)
    c = st.contacts[1]
    c2 = round_trip(c)
    assert c2.to_dict() == c.to_dict() and np.array_equal(c2.vertices, c.vertices)
    m = stance.Model.small_humanoid()
    m2 = round_trip(m)
    q = m.neutral()
    q[:3] += [0.3, -0.2, 0.1]
    assert np.array_equal(m2.centroidal_map(q), m.centroidal_map(q))


def test_results_round_trip() -> None:
    st = stance.Stance.from_scene("robust-equilibrium")
    gravities = [[1.0, 0, -9.81], [-1.0, 0, -9.81], [0, 1.0, -9.81]]
    coms = np.random.default_rng(1).uniform(-0.5, 0.5, size=(100, 3)) + [0, 0, 1.0]
    objects = [
        st.giwc(),
        st.static_equilibrium_polygon(),
        st.robust_static_region(gravities),
        st.supporting_forces([0, 0, 1.0]),
        stance.span_to_face(np.eye(3)),
        stance.face_to_span(-np.eye(3)),
        stance.topp([0, 0.5, 1], np.tile([1.0, -1.0], (3, 1)), np.zeros((3, 2)), -np.ones((3, 2))),
        stance.retime("double-support", [[0, 0.05, 0.8], [0, -0.05, 0.8]]),
    ]
    for o in objects:
        o2 = round_trip(o)
        assert type(o2) is type(o)
        for name in dir(o):
            if name.startswith("_") or callable(getattr(o, name)):
                continue
            a, b = getattr(o, name), getattr(o2, name)
            if isinstance(a, np.ndarray):
                assert np.array_equal(a, b, equal_nan=True), (type(o).__name__, name)
            elif isinstance(a, float) and np.isnan(a):
                assert np.isnan(b)
            else:
                assert a == b or (isinstance(a, dict) and a.keys() == b.keys()), (type(o).__name__, name)
    region = objects[2]
    assert np.array_equal(round_trip(region).contains(coms), region.contains(coms))
    assert round_trip(objects[0]).certified
