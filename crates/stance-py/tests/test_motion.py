"""stance.motion returns what `stance motion` writes."""

from __future__ import annotations

import json
import os
import shutil
import subprocess

import numpy as np
import pytest

import stance

from conftest import ROOT


def cli() -> str:
    for build in ("release", "debug"):
        exe = ROOT / "target" / build / "stance"
        if exe.is_file():
            return str(exe)
    found = shutil.which("stance")
    if found is None:
        pytest.skip("the stance command line is not built (cargo build -p stance-cli)")
    return found


def test_motion_equals_the_command_line() -> None:
    r = stance.motion("small-sway")
    out = subprocess.run([cli(), "motion", "small-sway"], check=True, capture_output=True, text=True,
                         env={**os.environ})
    ref = json.loads(out.stdout)
    assert r.status == ref["status"] == "optimal"
    assert r.duration == pytest.approx(ref["duration"], rel=1e-12)
    assert set(r.keys()) == set(ref.keys())
    assert len(r.segments) == len(ref["segments"])
    assert np.allclose(r.trajectory.t, ref["trajectory"]["t"])
    assert r.checks.samples_without_forces == ref["checks"]["samples_without_forces"]
    # The JSON text round-trips.
    assert json.loads(r.to_json())["duration"] == r.duration


def test_motion_options() -> None:
    a = stance.motion("small-sway", checks=False)
    b = stance.motion("small-sway", rest_to_rest=True, checks=False)
    assert a.duration <= b.duration
    fast = stance.motion("small-sway", time_scale=1.5)
    assert fast.checks.samples_without_forces > 0
    # the checks every 1 ms by default, or at their own step
    coarse = stance.motion("small-sway", check_dt=0.01)
    assert coarse.checks.samples < stance.motion("small-sway").checks.samples / 5


def test_paper_experiment_on_jvrc1() -> None:
    try:
        stance.Model.jvrc1()
    except stance.NotInstalledError:
        pytest.skip("JVRC-1's URDF is not installed (pip install jvrc-description)")
    r = stance.motion("stair-climbing", checks=False)
    assert r.status == "optimal"
    assert 4.0 < r.duration < 6.0


def test_missing_jvrc1_is_a_not_installed_error(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setenv("STANCE_JVRC1_URDF", "/no/such/jvrc1.urdf")
    with pytest.raises(stance.NotInstalledError, match="pip install jvrc-description"):
        stance.motion("stair-climbing")
    with pytest.raises(ImportError):  # NotInstalledError is an ImportError too
        stance.motion("box-climbing")


def test_motion_without_limits_is_faster_and_exceeds_them() -> None:
    limited = stance.motion("small-sway", dt=0.005)
    free = stance.motion("small-sway", dt=0.005, limits=False)
    assert limited.status == free.status == "optimal"
    assert free.duration < limited.duration
    assert limited.checks.max_torque_ratio <= 1.0 + 1e-6
    assert free.checks.max_torque_ratio > 1.0
