#!/usr/bin/env python3
"""Side-by-side benchmark of `stance retime-joints` against toppra on fixed-base arms: the UR5
and the Panda of PyPI `example-robot-data`, three joint paths each, under joint velocity,
acceleration and torque limits.

Run from the project root, with the virtualenv of `scripts/setup-venv.sh --peers`:

    "${STANCE_VENV:-.venv}/bin/python" bench/peers/joints.py [--quick] [--repeat N]

For every case:
1. the path file is written (URDF, joints, waypoints, limits, grid, interpolation
   discretization, no refinement: the grid as given, as toppra solves it);
2. toppra 0.6.10 solves the same problem: `SplineInterpolator` (not-a-knot, SciPy's
   CubicSpline) through the same waypoints at the same knots, `JointVelocityConstraint`,
   `JointAccelerationConstraint` and `JointTorqueConstraint` (Pinocchio's `rnea` as `inv_dyn`,
   no friction), all with first-order interpolation, the same grid, `TOPPRA` with its default
   seidel solver, rest to rest;
3. answers first: the durations must agree within 1e-4 relative (the run stops otherwise);
4. timings, in rounds (the Rust runner `crates/stance-motion/examples/bench_joints.rs`, which times
   rows + TOPP in one process; then toppra building its constraints on the grid, which
   evaluates their parameters with Pinocchio's RNEA, and solving), medians, and the ratio.
   Both sides build the robot model and the spline once, outside the timing.
"""

import argparse
import importlib.metadata
import json
import os
import statistics
import subprocess
import sys
import sysconfig
import tempfile
import time

import numpy as np
import pinocchio as pin
import toppra
import toppra.algorithm as algo
import toppra.constraint as tc

# The binaries run here find JVRC-1 and MuJoCo in this virtualenv (the one running this script).
os.environ.setdefault("STANCE_VENV", sys.prefix)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROBOTS = os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix", "share",
                      "example-robot-data", "robots")
DURATION_TOL = 1e-4


def urdf(name):
    return {
        "ur5": os.path.join(ROBOTS, "ur_description", "urdf", "ur5_robot.urdf"),
        "panda": os.path.join(ROBOTS, "panda_description", "urdf", "panda.urdf"),
    }[name]


LOCKED = {"ur5": {}, "panda": {"panda_finger_joint1": 0.02, "panda_finger_joint2": 0.02}}


def cases():
    """(name, robot, waypoints, acceleration limit): three paths per arm. The first is a short
    reach, the second a random 5-waypoint path (fixed seed) and the third a long swing of the
    heavy joints, where the torque limits bind."""
    rng = np.random.default_rng(27)
    ur5 = [
        ("ur5-reach", [[0.0, -1.5, 1.2, -1.0, -1.5, 0.0], [1.0, -1.0, 0.6, -0.5, -1.0, 0.5],
                       [2.0, -1.4, 1.0, -1.2, -1.6, 1.0]], 10.0),
        ("ur5-random", (rng.uniform(-1.5, 1.5, (5, 6)) + [0, -1.5, 0, -1.5, 0, 0]).tolist(), 8.0),
        ("ur5-swing", [[-2.5, -0.3, 0.2, 0.0, 0.0, 0.0], [0.0, -1.2, 0.1, -1.0, 1.0, 0.5],
                       [2.5, -0.3, 0.2, 0.0, 0.0, 1.0]], 40.0),
    ]
    panda = [
        ("panda-reach", [[0.0, -0.5, 0.0, -2.0, 0.0, 1.6, 0.8], [0.8, 0.2, -0.3, -1.6, 0.3, 1.9, 0.2],
                         [1.4, -0.2, 0.2, -2.3, -0.2, 2.2, -0.5]], 10.0),
        ("panda-random", (rng.uniform(-1.0, 1.0, (5, 7)) * [2.0, 1.2, 2.0, 0.8, 2.0, 1.2, 2.0]
                          + [0, 0, 0, -1.6, 0, 1.8, 0]).tolist(), 8.0),
        ("panda-swing", [[-2.0, 0.8, 0.0, -1.0, 0.0, 2.0, 0.0], [0.0, 1.5, 0.0, -0.4, 0.0, 2.5, 0.0],
                         [2.0, 0.8, 0.0, -1.0, 0.0, 2.0, 0.0]], 40.0),
    ]
    return [(n, "ur5", w, a) for n, w, a in ur5] + [(n, "panda", w, a) for n, w, a in panda]


def model_of(robot):
    full = pin.buildModelFromUrdf(urdf(robot))
    locked = LOCKED[robot]
    if not locked:
        return full
    q = pin.neutral(full)
    ids = []
    for name, value in locked.items():
        jid = full.getJointId(name)
        q[full.joints[jid].idx_q] = value
        ids.append(jid)
    return pin.buildReducedModel(full, ids, q)


def write_spec(path, robot, waypoints, acc, grid_points):
    lines = [
        f'urdf = "{urdf(robot)}"',
        "waypoints = " + json.dumps(waypoints),
        f"grid_points = {grid_points}",
        'discretization = "interpolation"',
        "max_violation_fraction = false",
        "[limits]",
        "velocity = 1.0",
        "torque = 1.0",
        f"acceleration = {acc}",
    ]
    if LOCKED[robot]:
        lines.insert(1, "locked = { " + ", ".join(f"{k} = {v}" for k, v in LOCKED[robot].items()) + " }")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


class ToppraCase:
    """toppra's side of one case: the model and the path built once; `solve` builds the
    constraints (their parameters on the grid: the inverse dynamics along the path) and the
    algorithm, and solves, which is the work our runner times (rows + TOPP)."""

    def __init__(self, robot, waypoints, acc, grid_points):
        self.model = model_of(robot)
        self.data = self.model.createData()
        n = self.model.nv
        way = np.array(waypoints)
        self.path = toppra.SplineInterpolator(np.linspace(0.0, 1.0, len(way)), way)  # not-a-knot
        self.vlim = np.stack([-self.model.velocityLimit, self.model.velocityLimit], axis=1)
        self.alim = np.stack([-np.full(n, acc), np.full(n, acc)], axis=1)
        self.tlim = np.stack([-self.model.effortLimit, self.model.effortLimit], axis=1)
        self.grid = np.linspace(0.0, 1.0, grid_points)

    def inv_dyn(self, q, v, a):
        return pin.rnea(self.model, self.data, q, v, a)

    def solve(self):
        interp = tc.DiscretizationType.Interpolation
        cv = tc.JointVelocityConstraint(self.vlim)
        ca = tc.JointAccelerationConstraint(self.alim, discretization_scheme=interp)
        ct = tc.JointTorqueConstraint(self.inv_dyn, self.tlim, np.zeros(self.model.nv),
                                      discretization_scheme=interp)
        inst = algo.TOPPRA([cv, ca, ct], self.path, gridpoints=self.grid,
                           solver_wrapper="seidel")
        _, sd, _ = inst.compute_parameterization(0, 0)
        return sd


def toppra_duration(grid, sd):
    sd = np.asarray(sd)
    dt = 2 * np.diff(grid) / (sd[:-1] + sd[1:])
    return float(np.sum(dt))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="fewer repeats")
    ap.add_argument("--repeat", type=int, default=None)
    ap.add_argument("--grid-points", type=int, default=101)
    args = ap.parse_args()
    repeat = args.repeat or (20 if args.quick else 200)
    rounds = 3 if args.quick else 5
    runner = os.path.join(ROOT, "target", "release", "examples", "bench_joints")
    subprocess.run(["cargo", "build", "--release", "-q", "-p", "stance-motion", "--example",
                    "bench_joints"], cwd=ROOT, check=True)
    print(f"toppra {importlib.metadata.version('toppra')}, Pinocchio {pin.__version__}; grid points "
          f"{args.grid_points}; {rounds} rounds of {repeat} solves")
    tmp = tempfile.mkdtemp(prefix="stance-joints-")
    rows = []
    for name, robot, waypoints, acc in cases():
        spec = os.path.join(tmp, name + ".toml")
        write_spec(spec, robot, waypoints, acc, args.grid_points)
        out = os.path.join(tmp, name + ".json")
        subprocess.run([runner, spec, "1", out], check=True)
        ours = json.load(open(out))
        case = ToppraCase(robot, waypoints, acc, args.grid_points)
        sd = case.solve()
        grid = case.grid
        if sd is None or ours["duration"] is None:
            sys.exit(f"{name}: no profile (ours {ours['status']}, toppra "
                     f"{'none' if sd is None else 'ok'})")
        d_t = toppra_duration(grid, sd)
        d_o = ours["duration"]
        rel = abs(d_o - d_t) / d_t
        if rel > DURATION_TOL:
            sys.exit(f"{name}: durations disagree: ours {d_o:.9f} s, toppra {d_t:.9f} s "
                     f"(relative {rel:.1e} > {DURATION_TOL:.0e})")
        rows.append({"name": name, "ours_s": d_o, "toppra_s": d_t, "rel": rel, "spec": spec,
                     "case": case})
        print(f"{name:14s} duration ours {d_o:.6f} s, toppra {d_t:.6f} s (relative {rel:.1e})")
    print("answers agree; timing")
    t_ours = {r["name"]: [] for r in rows}
    t_peer = {r["name"]: [] for r in rows}
    for _ in range(rounds):
        for r in rows:
            out = os.path.join(tmp, r["name"] + "-t.json")
            subprocess.run([runner, r["spec"], str(repeat), out], check=True)
            t_ours[r["name"]].append(json.load(open(out))["retime_us_median"])
        for r in rows:
            ts = []
            for _ in range(max(3, repeat // 10)):
                t = time.perf_counter()
                r["case"].solve()
                ts.append((time.perf_counter() - t) * 1e6)
            t_peer[r["name"]].append(statistics.median(ts))
    print()
    print("| path | duration (s) | toppra (s) | relative difference | ours (us) | toppra (us) | speed-up |")
    print("|---|---|---|---|---|---|---|")
    speedups = []
    for r in rows:
        o = statistics.median(t_ours[r["name"]])
        p = statistics.median(t_peer[r["name"]])
        speedups.append(p / o)
        print(f"| {r['name']} | {r['ours_s']:.6f} | {r['toppra_s']:.6f} | {r['rel']:.1e} | "
              f"{o:.0f} | {p:.0f} | x{p / o:.1f} |")
    geo = float(np.exp(np.mean(np.log(speedups))))
    print(f"\nspeed-up: smallest x{min(speedups):.1f}, geometric mean x{geo:.1f}")


if __name__ == "__main__":
    main()
