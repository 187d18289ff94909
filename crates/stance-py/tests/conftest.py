"""Shared fixtures: the repository's test data (goldens from the peers) and helpers."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Dict

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]
TESTDATA = ROOT / "testdata"


def load(rel: str) -> Dict[str, Any]:
    with open(TESTDATA / rel) as f:
        return json.load(f)  # type: ignore[no-any-return]


def same_rows_up_to_scaling(ours: np.ndarray, reference: np.ndarray, angle: float = 1e-9) -> bool:
    """Every row of each matrix equals a row of the other up to positive scaling (the angle
    between them at most `angle`, measured as the distance of the unit rows)."""
    a = np.asarray(ours, dtype=float)
    b = np.asarray(reference, dtype=float)
    if a.shape[0] != b.shape[0]:
        return False
    if a.shape[0] == 0:
        return True
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = b / np.linalg.norm(b, axis=1, keepdims=True)
    dist = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2)
    return bool(dist.min(axis=1).max() <= angle and dist.min(axis=0).max() <= angle)


def same_span(a: np.ndarray, b: np.ndarray, tol: float = 1e-9) -> bool:
    """The rows of a and b span the same subspace."""
    if a.shape[0] != b.shape[0]:
        return False
    if a.shape[0] == 0:
        return True
    ra = np.linalg.matrix_rank(a, tol)
    return bool(ra == np.linalg.matrix_rank(np.vstack([a, b]), tol) == np.linalg.matrix_rank(b, tol))


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20261126)
