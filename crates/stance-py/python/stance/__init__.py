"""stance: multi-contact stability of legged robots, in Rust, from Python.

Caron, Pham and Nakamura, "Leveraging Cone Double Description for Multi-contact Stability of
Humanoids with Applications to Statics and Dynamics" (RSS 2015), with NumPy in and out.

Cones (generators and facets as rows)
    span_to_face(V) -> FaceForm       span(V) = {x : facets @ x <= 0, equations @ x = 0}
    face_to_span(U, E=None) -> SpanForm
Contacts and stances (SI units; gravity (0, 0, -9.81) by default)
    Contact.rectangle / point / polygon
    Stance(contacts, mass, gravity) and Stance.from_scene(path | dict | name):
    giwc() (U_stance: U @ w_GI <= 0 at the world origin), static_equilibrium_polygon(),
    is_static_equilibrium(coms), robust_static_region(gravities),
    is_robust_static_equilibrium(coms, gravities), supporting_forces(com, ...)
Dynamics
    topp(s, a, b, c, ...): time-optimal parameterization under a u + b x + c <= 0 (u = s'',
    x = s'^2); retime(stance, com_waypoints, ...): eq. 14 along a CoM path
Whole body
    Model.from_urdf(path, locked=...), Model.jvrc1(): centroidal quantities with Pinocchio's
    conventions; motion(file | name, limits=True): the result of ``stance motion``
Fixed-base robots
    retime_joints(urdf, waypoints, limits={...}): a joint path retimed under joint velocity,
    acceleration and torque limits (``stance retime-joints``, toppra's problem)
pypoman users
    ``from stance import pypoman`` for pypoman's names and conventions.

Bad input raises ``InputError`` (a ``ValueError``); negative outcomes are values.
"""

from __future__ import annotations

import os as _os

from . import errors
from ._convert import Result, jvrc1_urdf as _jvrc1_urdf
from ._stance import (
    Contact,
    FaceForm,
    Giwc,
    Model,
    Polygon,
    RobustRegion,
    SpanForm,
    Stance,
    SupportingForces,
    ToppResult,
    __version__,
    face_to_span,
    motion,
    retime,
    retime_joints,
    span_to_face,
    topp,
)
from .errors import InputError, NotInstalledError, StanceError, UncertifiedError

# The whole-body pipeline finds JVRC-1's URDF through this variable: point it at the
# jvrc-description package of this environment (set once, at import, before any worker thread).
if "STANCE_JVRC1_URDF" not in _os.environ:
    _found = _jvrc1_urdf()
    if _found is not None:
        _os.environ["STANCE_JVRC1_URDF"] = _found

__all__ = [
    "Contact",
    "FaceForm",
    "Giwc",
    "InputError",
    "Model",
    "NotInstalledError",
    "Polygon",
    "Result",
    "RobustRegion",
    "SpanForm",
    "Stance",
    "StanceError",
    "SupportingForces",
    "ToppResult",
    "UncertifiedError",
    "__version__",
    "errors",
    "face_to_span",
    "motion",
    "retime",
    "retime_joints",
    "span_to_face",
    "topp",
]
