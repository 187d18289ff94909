"""stance.retime_joints: a fixed-base joint path under joint velocity, acceleration and torque
limits, as ``stance retime-joints``; against toppra when it is installed (the peers)."""

from __future__ import annotations

import importlib.util
import json
import subprocess

import numpy as np
import pytest

import stance

from conftest import ROOT
from test_motion import cli

ARM = ROOT / "models" / "three_link_arm.urdf"
WAYPOINTS = [[0.0, 0.3, 0.5, 0.0], [1.0, -0.5, 1.2, 2.0], [2.0, 0.4, 0.3, 4.0]]


def test_retime_joints_keeps_every_ratio_at_most_one() -> None:
    r = stance.retime_joints(ARM, np.array(WAYPOINTS), limits={"acceleration": 6.0}, dt=0.002)
    assert r.status == "optimal"
    for key in ("max_velocity_ratio", "max_acceleration_ratio", "max_torque_ratio"):
        assert r.checks[key] <= 1.0 + 1e-3
    assert r.binding["acceleration"] > 0
    assert r.trajectory.joint_names == ["yaw", "shoulder", "elbow", "wrist"]


def test_retime_joints_equals_the_command_line(tmp_path) -> None:
    f = tmp_path / "arm.toml"
    f.write_text(f'urdf = "{ARM}"\nwaypoints = {json.dumps(WAYPOINTS)}\n[limits]\n'
                 'acceleration = { default = 6.0, wrist = 20.0 }\n')
    out = subprocess.run([cli(), "retime-joints", str(f)], check=True, capture_output=True,
                         text=True)
    ref = json.loads(out.stdout)
    r = stance.retime_joints(ARM, WAYPOINTS, limits={"acceleration": {"default": 6.0, "wrist": 20.0}})
    assert r.duration == pytest.approx(ref["duration"], rel=1e-12)
    assert set(r.keys()) == set(ref.keys())


def test_bad_input_is_an_input_error() -> None:
    with pytest.raises(stance.InputError, match="elbw"):
        stance.retime_joints(ARM, WAYPOINTS, limits={"acceleration": {"elbw": 3.0}})
    with pytest.raises(stance.InputError, match="waypoint 1"):
        stance.retime_joints(ARM, [[0.0, 0.3, 0.5, 0.0], [1.0, -0.5, 1.2]])
    with pytest.raises(stance.InputError, match="limits.torque"):
        stance.retime_joints(ARM, WAYPOINTS, limits={"torque": -1.0})


@pytest.mark.skipif(importlib.util.find_spec("toppra") is None, reason="toppra is not installed")
def test_retime_joints_agrees_with_toppra() -> None:
    """The arm's path, retimed by toppra with the same limits (velocity and torque of the URDF,
    Pinocchio's RNEA; acceleration 6 rad/s^2), grid and discretization: the same duration."""
    import pinocchio as pin
    import toppra
    import toppra.algorithm as algo
    import toppra.constraint as tc

    model = pin.buildModelFromUrdf(str(ARM))
    data = model.createData()
    n = model.nv
    # the continuous wrist: Pinocchio takes (cos, sin); toppra's path is in angles
    assert model.nq == n + 1

    def q_of(theta: np.ndarray) -> np.ndarray:
        return np.concatenate([theta[:3], [np.cos(theta[3]), np.sin(theta[3])]])

    def inv_dyn(q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
        return pin.rnea(model, data, q_of(q), v, a)

    path = toppra.SplineInterpolator(np.linspace(0, 1, 3), np.array(WAYPOINTS))
    vlim = np.stack([-model.velocityLimit, model.velocityLimit], axis=1)
    tlim = np.stack([-model.effortLimit, model.effortLimit], axis=1)
    alim = np.stack([-np.full(n, 6.0), np.full(n, 6.0)], axis=1)
    interp = tc.DiscretizationType.Interpolation
    cons = [tc.JointVelocityConstraint(vlim),
            tc.JointAccelerationConstraint(alim, discretization_scheme=interp),
            tc.JointTorqueConstraint(inv_dyn, tlim, np.zeros(n), discretization_scheme=interp)]
    grid = np.linspace(0, 1, 101)
    inst = algo.TOPPRA(cons, path, gridpoints=grid, solver_wrapper="seidel")
    _, sd, _ = inst.compute_parameterization(0, 0)
    d_toppra = float(np.sum(2 * np.diff(grid) / (sd[:-1] + sd[1:])))
    r = stance.retime_joints(ARM, WAYPOINTS, limits={"acceleration": 6.0},
                             max_violation_fraction=None)
    assert r.duration == pytest.approx(d_toppra, rel=1e-4)
