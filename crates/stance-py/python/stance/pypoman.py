"""Drop-in replacements for pypoman's duality functions, with pypoman's names and conventions
(generators as **columns**, ``A x <= b``), computed by stance's certified double description.

Switch with one import::

    from stance import pypoman   # instead of: import pypoman

Differences, all in favour of correct answers:

- rows are normalized (``|F_i| = 1``; ``|A_i| = 1`` with ``b_i`` scaled alike);
- a cone or polytope that is not full-dimensional gets its equations as pairs of inequalities
  (``e x <= 0`` and ``-e x <= 0``); pypoman 2.0 returns only one side of them, or none (a cone in
  a plane of R^3 comes back as a wedge of R^3);
- an answer that cannot be certified raises ``stance.UncertifiedError`` instead of being
  returned.
"""

from __future__ import annotations

from typing import List, Sequence, Tuple, Union

import numpy as np

from ._stance import face_to_span, span_to_face
from .errors import InputError

__all__ = [
    "ConversionError",
    "compute_cone_face_matrix",
    "compute_polytope_halfspaces",
    "compute_polytope_vertices",
]

ArrayLike = Union[np.ndarray, Sequence[Sequence[float]]]


class ConversionError(InputError):
    """The input does not describe what the function converts (e.g. an unbounded polyhedron
    given to ``compute_polytope_vertices``); pypoman's exception of the same name."""


def _with_equations(facets: np.ndarray, equations: np.ndarray) -> np.ndarray:
    if equations.shape[0] == 0:
        return facets
    return np.vstack([facets, equations, -equations])


def compute_cone_face_matrix(S: ArrayLike) -> np.ndarray:
    """Face matrix ``F`` of the cone spanned by the **columns** of ``S``: ``{x : F x <= 0}``."""
    S = np.asarray(S, dtype=float)
    if S.ndim != 2:
        raise InputError(f"S must be a 2-D array (generators as columns), got shape {S.shape}")
    face = span_to_face(S.T)
    return _with_equations(face.facets, face.equations)


def _homogenize_vertices(vertices: Union[ArrayLike, List[np.ndarray]]) -> np.ndarray:
    V = np.asarray(vertices, dtype=float)
    if V.ndim != 2 or V.shape[0] == 0:
        raise InputError(f"vertices must be a non-empty list of points (n, d), got shape {V.shape}")
    return np.hstack([V, np.ones((V.shape[0], 1))])


def compute_polytope_halfspaces(
    vertices: Union[ArrayLike, List[np.ndarray]],
) -> Tuple[np.ndarray, np.ndarray]:
    """Half-space representation ``(A, b)``, ``A x <= b``, of the convex hull of ``vertices``.

    The hull is the section ``t = 1`` of the cone spanned by the ``(v_i, 1)``: its facets
    ``(a, a_0)`` (``a . v + a_0 t <= 0``) are the half-spaces ``a . x <= -a_0``.
    """
    H = _homogenize_vertices(vertices)
    face = span_to_face(H)
    rows = _with_equations(face.facets, face.equations)
    a, a0 = rows[:, :-1], rows[:, -1]
    norms = np.linalg.norm(a, axis=1)
    keep = norms > 1e-12 * max(1.0, float(np.abs(a0).max(initial=0.0)))
    a, a0, norms = a[keep], a0[keep], norms[keep]
    return a / norms[:, None], -a0 / norms


def compute_polytope_vertices(A: ArrayLike, b: ArrayLike) -> List[np.ndarray]:
    """Vertices of the polytope ``{x : A x <= b}``, as a list of arrays.

    The polytope is the section ``t = 1`` of the cone ``{(x, t) : A x - b t <= 0, t >= 0}``:
    its generators with ``t > 0`` are the vertices (scaled by ``t``); a generator with ``t = 0``
    or a lineality direction means the polyhedron is unbounded (``ConversionError``).
    """
    A = np.asarray(A, dtype=float)
    b = np.asarray(b, dtype=float).reshape(-1)
    if A.ndim != 2 or A.shape[0] != b.shape[0]:
        raise InputError(f"A must be (m, n) and b (m,), got shapes {A.shape} and {b.shape}")
    n = A.shape[1]
    U = np.vstack([np.hstack([A, -b[:, None]]), np.concatenate([np.zeros(n), [-1.0]])[None, :]])
    span = face_to_span(U)
    G = span.generators
    if span.lineality.shape[0] > 0:
        raise ConversionError("Polyhedron is not a polytope: it contains a line")
    if G.shape[0] == 0:
        return []
    t = G[:, -1]
    scale = np.linalg.norm(G, axis=1)
    if np.any(t <= 1e-10 * scale):
        raise ConversionError("Polyhedron is not a polytope: it contains a ray")
    return [g[:-1] / g[-1] for g in G]
