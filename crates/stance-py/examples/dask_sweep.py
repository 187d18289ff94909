"""Fan a stance sweep out over a Dask cluster: random stances (two feet anywhere on the ground,
half of them with a hand on a wall), each with its GIWC, its static-equilibrium polygon and a
batch of CoM tests; the same answers as the serial loop, and the measured speed-up.

    python crates/stance-py/examples/dask_sweep.py [--stances 4000] [--workers 2]

Stances are built inside the tasks from their seeds (a task ships a few integers, not
objects); objects would pickle too (every stance object does).
"""

from __future__ import annotations

import argparse
import os
import time
from typing import List, Sequence

import numpy as np

import stance


def random_stance(seed: int) -> stance.Stance:
    rng = np.random.default_rng(seed)
    contacts = []
    for name, y in (("LF", 0.1), ("RF", -0.1)):
        yaw = rng.uniform(-0.4, 0.4)
        R = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
        p = [rng.uniform(-0.15, 0.15), y + rng.uniform(-0.05, 0.05), rng.uniform(0, 0.2)]
        contacts.append(stance.Contact.rectangle(p, R, 0.11, 0.065, rng.uniform(0.4, 1.0), name=name))
    if seed % 2:
        # A hand on a wall in front (the contact's z axis, its normal, points back at the robot).
        R = np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], dtype=float)
        p = [rng.uniform(0.4, 0.6), rng.uniform(-0.3, 0.3), rng.uniform(0.8, 1.2)]
        contacts.append(stance.Contact.rectangle(p, R, 0.04, 0.03, rng.uniform(0.3, 0.8), name="RH"))
    return stance.Stance(contacts, mass=40.0)


# The CoMs every stance is tested on.
COMS = np.stack(np.meshgrid(np.linspace(-0.3, 0.3, 25), np.linspace(-0.3, 0.3, 25), [0.8]), -1).reshape(-1, 3)


def evaluate(seeds: Sequence[int]) -> np.ndarray:
    """Per stance: GIWC facets, polygon vertices, polygon area, stable CoMs of the grid."""
    out = np.zeros((len(seeds), 4))
    for k, seed in enumerate(seeds):
        st = random_stance(seed)
        poly = st.static_equilibrium_polygon()
        v = poly.vertices
        area = 0.5 * abs(np.dot(v[:, 0], np.roll(v[:, 1], -1)) - np.dot(v[:, 1], np.roll(v[:, 0], -1))) if len(v) > 2 else 0.0
        out[k] = [st.giwc().facets.shape[0], len(v), area, st.is_static_equilibrium(COMS).sum()]
    return out


def chunks(n: int, size: int) -> List[List[int]]:
    return [list(range(i, min(n, i + size))) for i in range(0, n, size)]


def run_dask(client, n: int, size: int) -> np.ndarray:  # type: ignore[no-untyped-def]
    futures = client.map(evaluate, chunks(n, size))
    return np.vstack(client.gather(futures))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--stances", type=int, default=4000)
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 2)
    ap.add_argument("--chunk", type=int, default=250)
    args = ap.parse_args()
    from dask.distributed import Client, LocalCluster

    t0 = time.perf_counter()
    serial = evaluate(range(args.stances))
    t_serial = time.perf_counter() - t0
    with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, Client(cluster) as client:
        run_dask(client, 2 * args.workers, 1)  # start-up: workers import stance
        t0 = time.perf_counter()
        fanned = run_dask(client, args.stances, args.chunk)
        t_dask = time.perf_counter() - t0
    assert np.array_equal(serial, fanned), "the fan-out changed an answer"
    print(f"{args.stances} stances: serial {t_serial:.2f} s ({1e6 * t_serial / args.stances:.0f} us per stance), "
          f"Dask with {args.workers} worker processes {t_dask:.2f} s: speed-up x{t_serial / t_dask:.2f}; "
          f"answers identical")


if __name__ == "__main__":
    main()
