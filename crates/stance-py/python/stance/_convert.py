"""Helpers of the native module: result dicts, JSON conversion, JVRC-1's URDF."""

from __future__ import annotations

import importlib.util
import json
import numbers
import os
from pathlib import Path
from typing import Any, Optional

import numpy as np


def to_builtin(obj: Any) -> Any:
    """``json.dumps`` default: NumPy arrays and scalars as plain lists and numbers."""
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, os.PathLike):
        return os.fspath(obj)
    raise TypeError(f"{type(obj).__name__} is not a number, list or dict")


def _numeric(x: Any) -> bool:
    return isinstance(x, numbers.Real) and not isinstance(x, bool)


def _is_numeric_tree(v: Any) -> bool:
    if _numeric(v):
        return True
    return isinstance(v, list) and len(v) > 0 and all(_is_numeric_tree(x) for x in v)


def _convert(v: Any) -> Any:
    if isinstance(v, dict):
        return Result(v)
    if isinstance(v, list):
        if v and _is_numeric_tree(v):
            try:
                return np.asarray(v, dtype=float)
            except ValueError:  # ragged
                pass
        return [_convert(x) for x in v]
    return v


class Result(dict):  # type: ignore[type-arg]
    """A result of ``stance.retime`` or ``stance.motion``: the JSON of the command line's
    ``stance retime`` / ``stance motion`` as a dict whose keys are also attributes, with
    rectangular lists of numbers as NumPy arrays (float)."""

    def __init__(self, d: Optional[dict] = None) -> None:  # type: ignore[type-arg]
        super().__init__({k: _convert(v) for k, v in (d or {}).items()})

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __dir__(self) -> list[str]:
        return sorted(set(super().__dir__()) | set(self.keys()))

    def to_json(self) -> str:
        """The result as JSON text (the command line's output)."""
        return json.dumps(self, default=to_builtin)


def jvrc1_urdf() -> Optional[str]:
    """The path of JVRC-1's URDF: ``$STANCE_JVRC1_URDF``, else PyPI ``jvrc-description``'s
    file in this environment, else None."""
    p = os.environ.get("STANCE_JVRC1_URDF")
    if p:
        return p
    spec = importlib.util.find_spec("jvrc_description")
    if spec is None or not spec.submodule_search_locations:
        return None
    for loc in spec.submodule_search_locations:
        candidate = Path(loc) / "urdf" / "jvrc1.urdf"
        if candidate.is_file():
            return str(candidate)
    return None
