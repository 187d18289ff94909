"""Scale out: the GIL is released during computations (other Python threads run), and a stance
sweep fanned out over a Dask local cluster gives the serial loop's answers."""

from __future__ import annotations

import importlib.util
import sys
import threading
import time
from pathlib import Path
from typing import Callable, List

import numpy as np
import pytest

import stance

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "dask_sweep.py"


def other_thread_runs_during(call: Callable[[], object]) -> int:
    """How many times another Python thread ran while `call` was in native code (a 1 ms margin
    on each side of the call keeps the Python-level parts of the call out)."""
    stamps: List[float] = []
    done = threading.Event()

    def spin() -> None:
        while not done.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0)

    spinner = threading.Thread(target=spin)
    spinner.start()
    time.sleep(0.01)
    t0 = time.perf_counter()
    call()
    t1 = time.perf_counter()
    done.set()
    spinner.join()
    if t1 - t0 < 0.01:
        pytest.skip(f"the call took {1e3 * (t1 - t0):.1f} ms: too short to observe")
    return sum(1 for t in stamps if t0 + 1e-3 < t < t1 - 1e-3)


def test_the_gil_is_released() -> None:
    st = stance.Stance.from_scene("stairs")
    coms = np.random.default_rng(0).uniform(-1, 1, size=(4_000_000, 3))
    assert other_thread_runs_during(lambda: st.is_static_equilibrium(coms)) > 10
    assert other_thread_runs_during(lambda: stance.motion("small-sway", checks=False)) > 10
    # Holding the GIL, nothing else runs (the measurement can tell).
    assert other_thread_runs_during(lambda: sum(range(3_000_000))) == 0


def load_example():  # type: ignore[no-untyped-def]
    spec = importlib.util.spec_from_file_location("dask_sweep", EXAMPLE)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules["dask_sweep"] = module
    spec.loader.exec_module(module)
    return module


def test_dask_fan_out_equals_the_serial_loop() -> None:
    pytest.importorskip("distributed")
    from dask.distributed import Client, LocalCluster

    sweep = load_example()
    serial = sweep.evaluate(range(120))
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
        # The workers import stance (installed) and the example (shipped, as a user would).
        client.upload_file(str(EXAMPLE))
        fanned = sweep.run_dask(client, 120, 25)
        # Objects travel too: a stance and its answers on a worker.
        st = sweep.random_stance(7)
        remote = client.submit(lambda s: s.is_static_equilibrium(sweep.COMS), st).result()
    assert np.array_equal(serial, fanned)
    assert np.array_equal(remote, st.is_static_equilibrium(sweep.COMS))
    assert serial[:, 0].min() > 0  # every GIWC has facets
