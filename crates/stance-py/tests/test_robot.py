"""Model: centroidal quantities against Pinocchio 4.1.0 (the repository's goldens, and live
when Pinocchio is installed), with Pinocchio's conventions."""

from __future__ import annotations

import numpy as np
import pytest

import stance

from conftest import ROOT, load

TOL = 1e-9


def model_for(name: str) -> stance.Model:
    d = load(f"robot/{name}.json")
    if name == "jvrc1":
        try:
            return stance.Model.jvrc1()
        except stance.NotInstalledError:
            pytest.skip("JVRC-1's URDF is not installed (pip install jvrc-description)")
    locked = {n: v for n, v in d["locked"]}
    return stance.Model.from_urdf(ROOT / d["urdf"], locked=locked)


@pytest.mark.parametrize("name", ["small_humanoid", "small_humanoid_locked", "jvrc1"])
def test_centroidal_quantities_equal_pinocchio(name: str) -> None:
    d = load(f"robot/{name}.json")
    m = model_for(name)
    assert (m.nq, m.nv) == (d["nq"], d["nv"])
    for case in d["cases"]:
        q, v = np.array(case["q"]), np.array(case["v"])
        scale = 1 + np.abs(case["centroidal_map"]).max()
        assert abs(m.mass - case["mass"]) <= TOL
        assert np.allclose(m.center_of_mass(q), case["com"], atol=TOL)
        assert np.allclose(m.com_jacobian(q), case["com_jacobian"], atol=TOL)
        assert np.allclose(m.centroidal_map(q), case["centroidal_map"], atol=TOL * scale)
        assert np.allclose(m.centroidal_map_dot_v(q, v), case["centroidal_map_dot_v"], atol=TOL * scale * (1 + np.abs(v).max()) ** 2)
        h = m.centroidal_momentum(q, v)
        assert np.allclose(h, np.array(case["centroidal_map"]) @ v, atol=TOL * scale * (1 + np.abs(v).max()))
        for frame, ref in case["frames"].items():
            R, p = m.frame_placement(frame, q)
            assert np.allclose(R, ref["rotation"], atol=TOL)
            assert np.allclose(p, ref["translation"], atol=TOL)


def test_live_pinocchio_on_random_configurations(rng: np.random.Generator) -> None:
    pin = pytest.importorskip("pinocchio")
    path = ROOT / "models" / "small_humanoid.urdf"
    pm = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    data = pm.createData()
    ours = stance.Model.from_urdf(path)
    for _ in range(10):
        q = pin.randomConfiguration(pm, -np.ones(pm.nq), np.ones(pm.nq))
        v = rng.normal(size=pm.nv)
        pin.ccrba(pm, data, q, v)
        assert np.allclose(ours.centroidal_map(q), data.Ag, atol=1e-9)
        assert np.allclose(ours.center_of_mass(q), data.com[0], atol=1e-12)


def test_model_inputs_are_checked() -> None:
    m = stance.Model.small_humanoid()
    with pytest.raises(stance.InputError, match=r"q must be a 1-D array of shape \(29,\)"):
        m.center_of_mass(np.zeros(3))
    q = m.neutral()
    q[8] = np.nan
    with pytest.raises(stance.InputError, match=r"q\[8\] is NaN"):
        m.center_of_mass(q)
    with pytest.raises(stance.InputError, match="no_such_frame"):
        m.frame_placement("no_such_frame", m.neutral())
    with pytest.raises(stance.InputError):
        stance.Model.from_urdf(ROOT / "no" / "such.urdf")
    with pytest.raises(stance.InputError):
        stance.Model.from_urdf_string("<robot name='x'>")


def test_moving_the_base_moves_the_com(rng: np.random.Generator) -> None:
    m = stance.Model.small_humanoid()
    q = m.neutral()
    c0 = m.center_of_mass(q)
    q[:3] += [1000.0, -20.0, 3.0]
    assert np.allclose(m.center_of_mass(q) - c0, [1000.0, -20.0, 3.0], atol=1e-9)
