#!/usr/bin/env python3
"""The Python package against the Python peers, Python to Python, in one run.

    "${STANCE_VENV:-.venv}/bin/python" bench/peers/python_api.py [--quick]

Needs the package (`pip install ./crates/stance-py`) and the peers (`scripts/setup-venv.sh
--peers`) in the same virtualenv. For every operation, on the same inputs:

- the peer from Python (pycddlib, pypoman, pypoman's Bretl projection, NumPy, toppra, Pinocchio);
- ours from Python (`import stance`);
- ours in Rust: the same call the binding makes, timed inside the extension
  (`stance._stance._bench_rust`), so that "Python - Rust" is what the binding adds.

Answers are compared before any time is reported (a disagreement is printed and the row gets
no ratio). Times are medians of interleaved rounds. Targets (issue 15): the binding adds
under 2 us per call; batch CoM tests under 50 ns per CoM; each Python-to-Python speed-up at
least half of the Rust-to-peer speed-up of the same operation in the same run (that is, Rust
time / Python time >= 0.5).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from typing import Callable, Dict, List, Tuple

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)

import cdd  # noqa: E402
import pinocchio as pin  # noqa: E402
import pypoman  # noqa: E402
import toppra  # noqa: E402
import toppra.algorithm as algo  # noqa: E402

import stance  # noqa: E402
from stance._stance import _bench_rust  # noqa: E402

import contact as peer_contact  # noqa: E402  (bench/peers/contact.py: the peers' methods)
import topp as peer_topp  # noqa: E402  (bench/peers/topp.py)

ROUNDS = 7


def per_call(f: Callable[[], object], min_time: float = 0.01) -> float:
    """Median over ROUNDS batches (each lasting at least min_time) of the mean seconds per
    call of f."""
    reps = 1
    while True:
        t = time.perf_counter()
        for _ in range(reps):
            f()
        if time.perf_counter() - t >= min_time:
            break
        reps *= 2
    v = []
    for _ in range(ROUNDS):
        t = time.perf_counter()
        for _ in range(reps):
            f()
        v.append((time.perf_counter() - t) / reps)
    return statistics.median(v)


def rust(op: str, args: tuple, min_time: float = 0.01) -> float:
    """Median over 7 blocks of the mean seconds per call, timed inside the extension (the
    estimator of `per_call`)."""
    reps = 1
    while min(_bench_rust(op, args, reps)) * reps < min_time / 7 and reps < 1 << 20:
        reps *= 4
    return statistics.median(_bench_rust(op, args, reps))


def interleaved(fns: Dict[str, Callable[[], float]], rounds: int = 3) -> Dict[str, float]:
    """Each timing function run `rounds` times in turn; the median of each."""
    out: Dict[str, List[float]] = {k: [] for k in fns}
    for _ in range(rounds):
        for k, f in fns.items():
            out[k].append(f())
    return {k: statistics.median(v) for k, v in out.items()}


def same_rows(a: np.ndarray, b: np.ndarray, tol: float = 1e-6) -> bool:
    return peer_contact.same_rows(a, b, tol)


Row = Tuple[str, str, str, float, float, float, bool]
ROWS: List[Row] = []


def record(op: str, case: str, peer: str, t_peer: float, t_py: float, t_rust: float, agree: bool) -> None:
    ROWS.append((op, case, peer, t_peer, t_py, t_rust, agree))


# ---- span -> face ----------------------------------------------------------------------------


def cone_cases() -> List[Tuple[str, np.ndarray]]:
    out = []
    for name in ["single_support_flat", "double_support_flat", "double_support_stairs", "tilted_foot_hand_ledge"]:
        with open(os.path.join(ROOT, "testdata", "cones", f"{name}.json")) as f:
            d = json.load(f)
        V = np.array([[float.fromhex(x) for x in r] for r in d["generators"]["float64_hex"]])
        out.append((name, V))
    return out


def bench_cones(quick: bool) -> None:
    for name, V in cone_cases():
        ours = stance.span_to_face(V)
        U_cdd, E_cdd = peer_contact.face_cdd(V)
        F_pp = pypoman.compute_cone_face_matrix(V.T)
        agree_cdd = same_rows(ours.facets, U_cdd) and E_cdd.shape[0] == ours.equations.shape[0]
        agree_pp = same_rows(ours.facets, F_pp) and ours.equations.shape[0] == 0
        t = interleaved(
            {
                "py": lambda: per_call(lambda: stance.span_to_face(V)),
                "rust": lambda: rust("span_to_face", (V,)),
                "cdd": lambda: per_call(lambda: peer_contact.face_cdd(V)),
                "pypoman": lambda: per_call(lambda: pypoman.compute_cone_face_matrix(V.T)),
            },
            1 if quick else 3,
        )
        record("span_to_face", f"{name} ({V.shape[0]} gen.)", "pycddlib float", t["cdd"], t["py"], t["rust"], agree_cdd)
        record("span_to_face", f"{name} ({V.shape[0]} gen.)", "pypoman", t["pypoman"], t["py"], t["rust"], agree_pp)


# ---- static-equilibrium polygon --------------------------------------------------------------


def bench_polygons(quick: bool) -> None:
    for name in ["double-support", "stairs", "box-climbing"]:
        st = stance.Stance.from_scene(name)
        scene = st.to_dict()
        ours = st.static_equilibrium_polygon()
        hull, _ = peer_contact.hull_polygon(scene)
        bretl = peer_contact.bretl_polygon(scene)
        agree_hull = peer_contact.hausdorff(hull, ours.vertices) < 1e-6
        # Bretl-Lall's polygon is an inner approximation that stops at its own precision: it
        # agrees when it lies inside ours and covers at least 99 % of its area.
        inside = (ours.A @ np.asarray(bretl).T - ours.b[:, None]).max() <= 1e-6
        covers = peer_contact.polygon_area(bretl) >= 0.99 * peer_contact.polygon_area(ours.vertices)
        agree_bretl = bool(inside and covers)
        t = interleaved(
            {
                "py": lambda: per_call(lambda: st.static_equilibrium_polygon()),
                "rust": lambda: rust("static_polygon", (st,)),
                "hull": lambda: per_call(lambda: peer_contact.hull_polygon(scene)),
                "bretl": lambda: per_call(lambda: peer_contact.bretl_polygon(scene)),
            },
            1 if quick else 3,
        )
        record("static polygon", name, "pymanoid's hull (pypoman + cdd)", t["hull"], t["py"], t["rust"], agree_hull)
        record("static polygon", name, "pypoman Bretl projection", t["bretl"], t["py"], t["rust"], agree_bretl)


# ---- robust CoM test -------------------------------------------------------------------------


def bench_robust(quick: bool) -> Dict[str, float]:
    st = stance.Stance.from_scene("robust-equilibrium")
    G = np.array(peer_contact.GRAVITIES)
    U = st.giwc().facets
    rng = np.random.default_rng(7)
    n = 100_000 if quick else 1_000_000
    P = np.column_stack([rng.uniform(-0.5, 0.8, n), rng.uniform(-0.6, 0.5, n), rng.uniform(0.3, 1.3, n)])
    ours = st.is_robust_static_equilibrium(P, G)
    theirs = peer_contact.robust_batch(U, G, P)
    region = st.robust_static_region(G)
    margin = np.array([region.margin(p) for p in P[:20000]])
    clear = np.abs(margin) > 1e-9
    agree = bool(np.array_equal(ours[:20000][clear], theirs[:20000][clear]))
    t = interleaved(
        {
            "py": lambda: per_call(lambda: st.is_robust_static_equilibrium(P, G), 0.05),
            "rust": lambda: rust("robust_batch", (st, G, P), 0.05),
            "numpy": lambda: per_call(lambda: peer_contact.robust_batch(U, G, P), 0.05),
        },
        1 if quick else 3,
    )
    record("robust CoM test, batch (per CoM)", f"{n} CoMs, 4 gravities", "NumPy", t["numpy"] / n, t["py"] / n, t["rust"] / n, agree)
    p = P[0]
    one = interleaved(
        {
            "py": lambda: per_call(lambda: region.contains(p)),
            "py_stance": lambda: per_call(lambda: st.is_robust_static_equilibrium(p, G)),
            "rust": lambda: rust("robust_batch", (st, G, P[:1])),
            "numpy": lambda: per_call(lambda: peer_contact.robust_one(U, G, p)),
        },
        1 if quick else 3,
    )
    agree_one = region.contains(p) == peer_contact.robust_one(U, G, p)
    record("robust CoM test, one CoM", "RobustRegion.contains(p)", "NumPy", one["numpy"], one["py"], one["rust"], agree_one)
    record("robust CoM test, one CoM", "Stance.is_robust_static_equilibrium(p, G)", "NumPy", one["numpy"], one["py_stance"], one["rust"], agree_one)
    return {"per_com_ns": 1e9 * t["py"] / n}


# ---- TOPP ------------------------------------------------------------------------------------


def bench_topp(quick: bool) -> None:
    for name in ["ds_flat_N100", "mc_minvel_N100"]:
        with open(os.path.join(ROOT, "testdata", "topp", f"{name}.json")) as f:
            d = json.load(f)
        s, a, b, c = (np.array(d[k]) for k in ("s", "a", "b", "c"))
        for disc in ["collocation", "interpolation"]:
            ours = stance.topp(s, a, b, c, discretization=disc)
            kind = peer_topp.DISC[disc]
            path = toppra.SplineInterpolator([0.0, 1.0], [[0.0], [1.0]])

            def toppra_solve() -> float:
                inst = algo.TOPPRA([peer_topp.CanonicalRows(a, b, c, kind)], path, gridpoints=s, solver_wrapper="seidel")
                sd = inst.compute_parameterization(0.0, 0.0)[1]
                return float(np.sum(2 * np.diff(s) / (sd[:-1] + sd[1:])))

            theirs = toppra_solve()
            agree = ours.duration is not None and -1e-5 <= (ours.duration - theirs) / theirs <= 1e-9
            t = interleaved(
                {
                    "py": lambda: per_call(lambda: stance.topp(s, a, b, c, discretization=disc)),
                    "rust": lambda: rust("topp", (s, a, b, c, disc)),
                    "toppra": lambda: per_call(toppra_solve),
                },
                1 if quick else 3,
            )
            record("TOPP", f"{name} {disc} ({a.shape[1]} rows)", "toppra 0.6.10 (seidel)", t["toppra"], t["py"], t["rust"], agree)


# ---- centroidal quantities -------------------------------------------------------------------


def bench_centroidal(quick: bool) -> None:
    ours = stance.Model.jvrc1()
    urdf = stance._convert.jvrc1_urdf()
    full = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    # The project's JVRC-1: fingers locked at 0 (stance_robot::jvrc1::FINGER_JOINTS).
    fingers = [f"{side}_{j}" for side in "RL" for j in ("UTHUMB", "LTHUMB", "UINDEX", "LINDEX", "ULITTLE", "LLITTLE")]
    pm = pin.buildReducedModel(full, [full.getJointId(n) for n in fingers], pin.neutral(full))
    data = pm.createData()
    assert pm.nq == ours.nq, (pm.nq, ours.nq)
    rng = np.random.default_rng(3)
    q = pin.randomConfiguration(pm, -np.ones(pm.nq), np.ones(pm.nq))
    v = rng.normal(size=pm.nv)
    pin.ccrba(pm, data, q, v)
    agree = bool(np.allclose(ours.centroidal_map(q), data.Ag, atol=1e-9))
    t = interleaved(
        {
            "py": lambda: per_call(lambda: ours.centroidal_map(q)),
            "rust": lambda: rust("centroidal_map", (ours, q)),
            "pin": lambda: per_call(lambda: pin.ccrba(pm, data, q, v)),
        },
        1 if quick else 3,
    )
    record("centroidal map A_g(q)", "JVRC-1 (nv = 38)", "Pinocchio 4.1.0 ccrba", t["pin"], t["py"], t["rust"], agree)


def bench_fixed_costs() -> List[Tuple[str, float, float]]:
    """What the binding adds to a call whose inputs and outputs are tiny: (call, Python, Rust),
    each the smallest of 7 interleaved measurements (differences of a microsecond drown in this
    machine's noise otherwise)."""
    m = stance.Model.small_humanoid()
    V = np.eye(3)
    s = np.array([0.0, 1.0])
    a = np.array([[1.0, -1.0], [1.0, -1.0]])
    b = np.zeros((2, 2))
    c = -np.ones((2, 2))
    st = stance.Stance.from_scene("robust-equilibrium")
    G = np.array(peer_contact.GRAVITIES)
    region = st.robust_static_region(G)
    p = np.array([0.0, 0.0, 1.0])
    q = m.neutral()
    cases: List[Tuple[str, Callable[[], object], Callable[[], float]]] = [
        ("a property read (`Model.nq`): the floor of any call", lambda: m.nq, lambda: 0.0),
        ("`span_to_face` of the positive orthant of R^3", lambda: stance.span_to_face(V), lambda: rust("span_to_face", (V,))),
        ("`topp` on 2 grid points, 2 rows", lambda: stance.topp(s, a, b, c), lambda: rust("topp", (s, a, b, c, "interpolation"))),
        ("`RobustRegion.contains` of one CoM", lambda: region.contains(p), lambda: rust("robust_batch", (st, G, p[None, :]))),
        ("`Stance.static_equilibrium_polygon`, 3 contacts", lambda: st.static_equilibrium_polygon(), lambda: rust("static_polygon", (st,))),
        ("`Model.centroidal_map`, small humanoid (nv = 27)", lambda: m.centroidal_map(q), lambda: rust("centroidal_map", (m, q))),
    ]
    out = []
    for name, call, in_rust in cases:
        py_t, rs_t = [], []
        for _ in range(7):
            py_t.append(per_call(call))
            rs_t.append(in_rust())
        out.append((name, min(py_t), min(rs_t)))
    return out


def fmt_time(t: float) -> str:
    if t < 1e-6:
        return f"{1e9 * t:.1f} ns"
    if t < 1e-3:
        return f"{1e6 * t:.2f} us"
    return f"{1e3 * t:.2f} ms"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="fewer rounds and CoMs (a smoke run)")
    args = ap.parse_args()
    from importlib.metadata import version

    peers = ", ".join(f"{p} {version(p)}" for p in ("numpy", "pycddlib", "pypoman", "toppra", "pin"))
    print(f"stance {stance.__version__}; {peers}; {os.cpu_count()} cores\n")
    bench_cones(args.quick)
    bench_polygons(args.quick)
    extra = bench_robust(args.quick)
    bench_topp(args.quick)
    bench_centroidal(args.quick)
    fixed = bench_fixed_costs()
    print("| operation | case | peer | peer (Python) | ours (Python) | ours (Rust) | binding adds "
          "| speed-up Python/Python | speed-up Rust/peer | ratio of the two (>= 0.5) | answers |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    worst_overhead = 0.0
    worst_ratio = 1e9
    for op, case, peer, tp, tpy, tr, agree in ROWS:
        added = tpy - tr
        if "per CoM" not in op:
            worst_overhead = max(worst_overhead, added)
        if agree:
            worst_ratio = min(worst_ratio, tr / tpy)
        ratio = f"{tr / tpy:.2f}" if agree else "-"
        sp_py = f"x{tp / tpy:.1f}" if agree else "disagree"
        sp_rs = f"x{tp / tr:.1f}" if agree else "-"
        print(f"| {op} | {case} | {peer} | {fmt_time(tp)} | {fmt_time(tpy)} | {fmt_time(tr)} | {fmt_time(added)} "
              f"| {sp_py} | {sp_rs} | {ratio} | {'agree' if agree else 'DISAGREE'} |")
    print("\n| call with tiny inputs and outputs | ours (Python) | ours (Rust) | binding adds |")
    print("|---|---|---|---|")
    for name, tpy, tr in fixed:
        print(f"| {name} | {fmt_time(tpy)} | {fmt_time(tr) if tr else '-'} | {fmt_time(tpy - tr) if tr else '-'} |")
    worst_fixed = max(tpy - tr for _, tpy, tr in fixed if tr)
    print(f"\nlargest time the binding adds to a call with tiny inputs: {fmt_time(worst_fixed)} (target < 2 us)")
    print(f"largest difference Python - Rust over the operations above (includes converting the inputs): {fmt_time(worst_overhead)}")
    print(f"batch robust CoM test from Python: {extra['per_com_ns']:.1f} ns per CoM (target < 50 ns)")
    print(f"smallest Rust time / Python time over the agreeing rows: {worst_ratio:.2f} (target >= 0.5)")


if __name__ == "__main__":
    main()
