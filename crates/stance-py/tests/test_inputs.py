"""Bad input raises InputError (a ValueError and a StanceError) naming what to fix; array-likes
of any layout give the same answers as C-contiguous float64 arrays."""

from __future__ import annotations

import numpy as np
import pytest

import stance
from stance import errors

STANCE = stance.Stance.from_scene("stairs")
COMS = np.array([[0.0, 0.0, 0.8], [0.1, 0.05, 0.8], [1.0, 0.0, 0.8], [0.05, -0.1, 0.7]])


def test_exception_tree() -> None:
    assert issubclass(errors.InputError, stance.StanceError)
    assert issubclass(errors.InputError, ValueError)
    assert issubclass(errors.UncertifiedError, stance.StanceError)
    assert issubclass(errors.NotInstalledError, ImportError)
    assert stance.InputError is errors.InputError


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: STANCE.is_static_equilibrium(np.zeros((4, 2))), r"coms must be an array of shape \(n, 3\).*\(4, 2\)"),
        (lambda: STANCE.is_static_equilibrium(np.zeros((2, 3, 1))), r"shape \(2, 3, 1\)"),
        (lambda: STANCE.is_static_equilibrium([[0, 0, np.nan]]), r"coms\[0, 2\] is NaN"),
        (lambda: STANCE.is_static_equilibrium([[0, 0, np.inf]]), r"coms\[0, 2\] is inf"),
        (lambda: STANCE.is_static_equilibrium("0 0 1"), "got a string"),
        (lambda: STANCE.is_static_equilibrium([["a", "b", "c"]]), "array of numbers"),
        (lambda: STANCE.is_static_equilibrium(None), "None"),
        (lambda: STANCE.is_static_equilibrium([[0, 0], [1]]), "array of numbers"),
        (lambda: STANCE.static_equilibrium_polygon(gravity=[0, 0]), r"gravity must be a 1-D array of shape \(3,\)"),
        (lambda: STANCE.static_equilibrium_polygon(gravity=[1.0, 0, 0]), "gravity"),
        (lambda: STANCE.robust_static_region([]), "gravit"),
        (lambda: stance.span_to_face(np.zeros(3)), r"generators must be a 2-D array"),
        (lambda: stance.face_to_span(np.eye(3), np.zeros((1, 2))), r"equations must be a 2-D array of shape \(n, 3\)"),
        (lambda: stance.Contact.rectangle([0, 0, 0], np.eye(3), -0.1, 0.05, 0.7), "half"),
        (lambda: stance.Contact.rectangle([0, 0, 0], 2 * np.eye(3), 0.1, 0.05, 0.7), "rotation"),
        (lambda: stance.Contact.rectangle([0, 0], np.eye(3), 0.1, 0.05, 0.7), "position"),
        (lambda: stance.Contact.point([0, 0, 0], friction=-1.0), "friction"),
        (lambda: stance.Contact.polygon([0, 0, 0], None, [[0, 0], [1, 0], [2, 0]], 0.5), "polygon"),
        (lambda: stance.Stance([], mass=10), "at least one contact"),
        (lambda: stance.Stance([1, 2], mass=10), r"contacts\[0\] is not a stance.Contact"),
        (lambda: stance.Stance(STANCE.contacts, mass=-1.0), "mass"),
        (lambda: stance.Stance(STANCE.contacts, mass=1.0, friction_sides=2), "sides"),
        (lambda: stance.Stance(STANCE.contacts, mass=1.0, friction_approximation="middle"), "outer"),
        (lambda: stance.topp([0, 1], [[1]], [[0]], [[-1]]), r"a must have shape \(2, m\)"),
        (lambda: stance.topp([0, 1, 0.5], np.ones((3, 1)), np.ones((3, 1)), np.ones((3, 1))), "increasing"),
        (lambda: stance.topp([0, 1], np.ones((2, 1)), np.ones((2, 2)), np.ones((2, 1))), "same number of rows"),
        (lambda: stance.topp([0, 1], np.ones((2, 1)), np.ones((2, 1)), [[1], [np.nan]]), r"c\[1, 0\] is NaN"),
        (lambda: stance.topp([0, 1], np.ones((2, 1)), np.ones((2, 1)), np.ones((2, 1)), discretization="euler"), "interpolation"),
        (lambda: stance.topp([0, 1], np.ones((2, 1)), np.ones((2, 1)), np.ones((2, 1)), sd_start=-1.0), "sd_start"),
        (lambda: stance.retime(STANCE, [[0, 0, 0.8]]), "waypoint"),
        (lambda: stance.retime(STANCE, [[0, 0, 0.8], [0.1, 0, 0.8]], interpolation="bezier"), "spline"),
        (lambda: stance.motion("no-such-motion"), "is neither a file nor a built-in motion"),
        (lambda: stance.motion("small-sway", grid=0), "grid"),
        (
            lambda: stance.Stance.from_scene({"mass": 39, "contacts": [["LF", [0, 0, 0], None, "point", 0.7]]}),
            "object with named fields",
        ),
    ],
)
def test_bad_input_raises_input_error(call, match: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(stance.InputError, match=match):
        call()


def test_array_likes_give_the_same_answers() -> None:
    ref = STANCE.is_static_equilibrium(COMS)
    assert ref.dtype == np.bool_ and ref.shape == (4,)
    wide = np.zeros((4, 6))
    wide[:, ::2] = COMS
    cases = [
        COMS.tolist(),  # lists
        tuple(map(tuple, COMS.tolist())),  # tuples
        np.asfortranarray(COMS),  # column-major
        wide[:, ::2],  # strided view
        COMS.astype(np.float32),  # another float type
        (COMS * 1000).astype(np.int64) / 1000,  # computed
        np.array([[0, 0, 1], [1, 0, 1]], dtype=np.int32),  # integers
    ]
    for c in cases[:-1]:
        assert np.array_equal(STANCE.is_static_equilibrium(c), ref if np.asarray(c).dtype != np.float32 else STANCE.is_static_equilibrium(np.asarray(c, dtype=float)))
    ints = cases[-1]
    assert np.array_equal(STANCE.is_static_equilibrium(ints), STANCE.is_static_equilibrium(np.asarray(ints, dtype=float)))
    # One CoM gives a bool.
    assert STANCE.is_static_equilibrium(COMS[0]) is True
    assert STANCE.is_static_equilibrium([1.0, 0.0, 0.8]) is False
    # An empty batch gives an empty array.
    assert STANCE.is_static_equilibrium(np.zeros((0, 3))).shape == (0,)
    # The input is not modified and still writable.
    c = COMS.copy()
    STANCE.is_static_equilibrium(c)
    assert np.array_equal(c, COMS) and c.flags.writeable


def test_span_to_face_of_array_likes() -> None:
    V = [[1, 0, 0], [0, 1, 0], [1, 1, 1]]
    a = stance.span_to_face(V)
    b = stance.span_to_face(np.asfortranarray(np.array(V, dtype=float)))
    assert np.array_equal(a.facets, b.facets)


def test_memory_layouts_do_not_change_answers() -> None:
    # Fortran order keeps the logical (row-major) meaning of every matrix argument.
    a = 0.3
    R = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    c1 = stance.Contact.rectangle([0, 0, 0], R, 0.1, 0.05, 0.7)
    c2 = stance.Contact.rectangle([0, 0, 0], np.asfortranarray(R), 0.1, 0.05, 0.7)
    assert np.array_equal(c1.rotation, c2.rotation) and np.array_equal(c1.rotation, R)
    s = np.linspace(0, 1, 21)
    A = np.tile([1.0, -1.0, 0.5], (21, 1))
    B = np.tile([0.0, 0.0, 1.0], (21, 1))
    C = np.tile([-1.0, -1.0, -2.0], (21, 1))
    ref = stance.topp(s, A, B, C)
    wide = np.zeros((21, 6))
    wide[:, ::2] = A
    for args in [
        (s, np.asfortranarray(A), np.asfortranarray(B), np.asfortranarray(C)),
        (np.linspace(0, 1, 41)[::2], wide[:, ::2], B.tolist(), C.astype(np.float32)),
    ]:
        r = stance.topp(*args)
        assert r.duration == ref.duration
    m = stance.Model.small_humanoid()
    q = m.neutral()
    q[:3] = [0.1, 0.2, 0.3]
    strided = np.zeros(2 * m.nq)
    strided[::2] = q
    assert np.array_equal(m.center_of_mass(strided[::2]), m.center_of_mass(q))


def test_undecided_dimension_is_uncertified_not_a_lost_direction() -> None:
    """A contact wrench cone 1e5 m from the origin: its two smallest directions are far above
    rounding but within the rank tolerance. It was a certified cone with two directions lost;
    now UncertifiedError, and the exact conversion gives the 6-D cone."""
    rows = []
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            r = np.array([1e5 + 0.1 * sx, 3e4 + 0.05 * sy, 0.0])
            for f in ([0.7, 0, 1], [-0.7, 0, 1], [0, 0.7, 1], [0, -0.7, 1]):
                f = np.array(f, float)
                rows.append(np.concatenate([f, np.cross(r, f)]))
    v = np.array(rows)
    with pytest.raises(stance.UncertifiedError, match="wrench"):
        stance.span_to_face(v)
    exact = stance.span_to_face(v, exact=True)
    assert exact.facets.shape == (32, 6)
    assert exact.equations.shape[0] == 0
