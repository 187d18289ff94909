"""span_to_face / face_to_span against cddlib's exact answers (the repository's goldens), the
pypoman drop-ins against pypoman, and the invariances of a cone conversion."""

from __future__ import annotations

import numpy as np
import pytest

import stance
from stance import pypoman as drop_in

from conftest import TESTDATA, load, same_rows_up_to_scaling, same_span

CASES = sorted(p.stem for p in (TESTDATA / "cones").glob("*.json"))

# cddlib's GMP mode on the float64 inputs themselves (testdata/cones/README.md).
EXACT_COUNTS = {
    "single_support_flat": 16,
    "surface_cwc_foot": 16,
    "double_support_flat": 32,
    "opposing_walls_friction": 0,
    "opposing_walls_frictionless": 4,
    "double_support_stairs": 282,
    "tilted_foot_hand_ledge": 249,
}


def generators(case: str) -> np.ndarray:
    d = load(f"cones/{case}.json")
    return np.array([[float.fromhex(x) for x in row] for row in d["generators"]["float64_hex"]])


@pytest.mark.parametrize("case", CASES)
def test_span_to_face_equals_cdd_exact(case: str) -> None:
    d = load(f"cones/{case}.json")
    ref = d["reference_cdd_gmp_exact_input"]
    out = stance.span_to_face(generators(case))
    assert out.certified
    assert same_rows_up_to_scaling(out.facets, np.array(ref["facets_float64"]).reshape(-1, 6))
    assert same_span(out.equations, np.array(ref["equations"], dtype=float).reshape(-1, 6))
    assert out.lineality.shape[0] == ref["lineality_dim"]
    # Rows are unit.
    if out.facets.size:
        assert np.allclose(np.linalg.norm(out.facets, axis=1), 1.0)


@pytest.mark.parametrize("case", CASES)
def test_exact_arithmetic_counts_equal_cdd_gmp(case: str) -> None:
    out = stance.span_to_face(generators(case), exact=True)
    assert out.certified
    assert out.facets.shape[0] == EXACT_COUNTS[case]


@pytest.mark.parametrize("case", CASES)
def test_every_generator_satisfies_every_facet(case: str) -> None:
    V = generators(case)
    out = stance.span_to_face(V)
    Vn = V / np.linalg.norm(V, axis=1, keepdims=True)
    if out.facets.size:
        assert (out.facets @ Vn.T).max() <= 1e-9
    if out.equations.size:
        assert np.abs(out.equations @ Vn.T).max() <= 1e-9


@pytest.mark.parametrize("case", ["double_support_flat", "tilted_foot_hand_ledge"])
def test_scaling_generators_and_reordering_leave_the_cone(case: str, rng: np.random.Generator) -> None:
    V = generators(case)
    base = stance.span_to_face(V)
    scales = 10.0 ** rng.uniform(-6, 6, size=V.shape[0])
    perm = rng.permutation(V.shape[0])
    scaled = stance.span_to_face((V * scales[:, None])[perm])
    assert same_rows_up_to_scaling(scaled.facets, base.facets, angle=1e-8)


def test_face_to_span_round_trip() -> None:
    V = generators("double_support_flat")
    face = stance.span_to_face(V)
    span = stance.face_to_span(face.facets, face.equations)
    assert span.certified
    # The extreme generators come back (up to scaling).
    extreme = V[face.extreme_generators]
    assert same_rows_up_to_scaling(span.generators, extreme, angle=1e-8)


def test_lineality_and_equations() -> None:
    # A half-plane of R^3 inside the plane z = 0: one facet, one equation, one line.
    V = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0]])
    out = stance.span_to_face(V)
    assert out.facets.shape == (1, 3)
    assert np.allclose(np.abs(out.equations), [[0, 0, 1]])
    assert out.lineality.shape == (1, 3)
    assert np.allclose(np.abs(out.lineality), [[1, 0, 0]])
    span = stance.face_to_span(out.facets, out.equations)
    assert span.lineality.shape == (1, 3)
    assert span.generators.shape == (1, 3)


# ---- pypoman drop-ins ------------------------------------------------------------------------


def random_polytope(rng: np.random.Generator, n: int, d: int) -> np.ndarray:
    return rng.normal(size=(n, d))


def test_polytope_halfspaces_contain_exactly_the_hull(rng: np.random.Generator) -> None:
    for d in (2, 3, 4):
        V = random_polytope(rng, 30, d)
        A, b = drop_in.compute_polytope_halfspaces(V)
        assert np.allclose(np.linalg.norm(A, axis=1), 1.0)
        assert (A @ V.T - b[:, None]).max() <= 1e-9
        # Every half-space is tight at d affinely independent vertices (a facet).
        for a, bi in zip(A, b):
            tight = V[np.abs(V @ a - bi) <= 1e-9]
            assert np.linalg.matrix_rank(tight[1:] - tight[0]) == d - 1
        W = drop_in.compute_polytope_vertices(A, b)
        # The vertices are the hull's extreme points, a subset of the input.
        for w in W:
            assert np.min(np.linalg.norm(V - w, axis=1)) <= 1e-8


def test_pypoman_drop_ins_agree_with_pypoman(rng: np.random.Generator) -> None:
    pypoman = pytest.importorskip("pypoman")
    for d in (2, 3):
        V = random_polytope(rng, 20, d)
        A0, b0 = pypoman.compute_polytope_halfspaces(list(V))
        A1, b1 = drop_in.compute_polytope_halfspaces(V)
        H0 = np.hstack([A0, -b0[:, None]])
        H1 = np.hstack([A1, -b1[:, None]])
        assert same_rows_up_to_scaling(H1, H0, angle=1e-7)
        W0 = np.array(pypoman.compute_polytope_vertices(A0, b0))
        W1 = np.array(drop_in.compute_polytope_vertices(A0, b0))
        assert W0.shape == W1.shape
        assert max(np.min(np.linalg.norm(W0 - w, axis=1)) for w in W1) <= 1e-8
    S = generators("single_support_flat").T  # generators as columns
    F0 = pypoman.compute_cone_face_matrix(S)
    F1 = drop_in.compute_cone_face_matrix(S)
    assert same_rows_up_to_scaling(F1, F0, angle=1e-8)


def test_drop_in_keeps_equations_of_flat_sets() -> None:
    # A triangle in the plane z = 0 of R^3: both sides of z = 0 (pypoman 2.0 returns one).
    A, b = drop_in.compute_polytope_halfspaces([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    assert np.all(A @ np.array([0.2, 0.2, 0.0]) <= b + 1e-12)
    assert np.any(A @ np.array([0.2, 0.2, 0.1]) > b)
    assert np.any(A @ np.array([0.2, 0.2, -0.1]) > b)
    # A cone in the plane z = 0 of R^3.
    F = drop_in.compute_cone_face_matrix(np.array([[1.0, 0, 0], [0, 1, 0]]).T)
    assert np.all(F @ np.array([1.0, 1.0, 0.0]) <= 1e-12)
    assert np.any(F @ np.array([1.0, 1.0, 0.1]) > 0)


def test_unbounded_polyhedron_is_a_conversion_error() -> None:
    with pytest.raises(drop_in.ConversionError):
        drop_in.compute_polytope_vertices(np.array([[-1.0, 0], [0, -1]]), np.zeros(2))
    with pytest.raises(stance.InputError):
        drop_in.compute_polytope_vertices(np.array([[1.0, 0]]), np.zeros(2))
