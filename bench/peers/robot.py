#!/usr/bin/env python3
"""Side-by-side benchmark: forward kinematics + CoM + A_g per configuration on JVRC-1 (fingers
locked), stance-robot (Rust) versus Pinocchio 4.1.0 from Python and, when it can be compiled,
Pinocchio's own C++.

Run from the project root, with the virtualenv of `scripts/setup-venv.sh --peers`:

    "${STANCE_VENV:-.venv}/bin/python" bench/peers/robot.py [--configs 1000] [--repeat 30]

Steps: 1000 random configurations (fixed seed); the Rust runner
(`crates/stance-robot/examples/bench_centroidal.rs`, release build) and Pinocchio compute CoM and
A_g for each; the answers are compared (max relative difference must be below 1e-9) before any
timing is printed. Timings are per configuration, median and minimum over timed chunks of
`--chunk` configurations (`--repeat` rounds over all of them). See bench/peers/robot.md.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
import pinocchio as pin

# The binaries run here find JVRC-1 and MuJoCo in this virtualenv (the one running this script).
os.environ.setdefault("STANCE_VENV", sys.prefix)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
FINGERS = ["R_UTHUMB", "R_LTHUMB", "R_UINDEX", "R_LINDEX", "R_ULITTLE", "R_LLITTLE",
           "L_UTHUMB", "L_LTHUMB", "L_UINDEX", "L_LINDEX", "L_ULITTLE", "L_LLITTLE"]
REL_TOL = 1e-9


def random_configuration(model, rng):
    q = pin.neutral(model)
    q[0:3] = rng.uniform(-1.0, 1.0, 3)
    quat = rng.normal(size=4)
    q[3:7] = quat / np.linalg.norm(quat)
    lo, hi = model.lowerPositionLimit[7:], model.upperPositionLimit[7:]
    q[7:] = rng.uniform(lo, hi)
    return q


def per_config_times(fn, qs, repeat, chunk):
    """(median, minimum) in ns per configuration over all timed chunks: `repeat` rounds over the
    configurations, each in chunks of `chunk` (short timed sections: a preemption by the
    scheduler on a shared machine spoils one chunk, not the round)."""
    times = []
    for _ in range(repeat):
        for start in range(0, len(qs), chunk):
            part = qs[start:start + chunk]
            t0 = time.perf_counter_ns()
            fn(part)
            times.append((time.perf_counter_ns() - t0) / len(part))
    return float(np.median(times)), float(np.min(times))


def rel_diff(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b)) / max(1.0, np.max(np.abs(b))))


def build_cpp(workdir):
    """Compiles bench/peers/robot_cpp.cpp against the Pinocchio of this virtualenv (headers and
    libraries ship with the `pin` wheel) and Eigen 3.4 headers (not in the wheel: the Debian
    package libeigen3-dev, or EIGEN3_INCLUDE_DIR). Returns the binary or None with a reason."""
    prefix = os.path.dirname(os.path.abspath(pin.__file__))
    while os.path.basename(prefix) != "cmeel.prefix" and os.path.dirname(prefix) != prefix:
        prefix = os.path.dirname(prefix)
    eigen = os.environ.get("EIGEN3_INCLUDE_DIR", "/usr/include/eigen3")
    cxx = shutil.which(os.environ.get("CXX", "g++"))
    if not os.path.isdir(os.path.join(prefix, "include", "pinocchio")):
        return None, "no Pinocchio headers in the virtualenv"
    if not os.path.isdir(os.path.join(eigen, "Eigen")):
        return None, f"no Eigen headers at {eigen} (apt-get install libeigen3-dev, or set EIGEN3_INCLUDE_DIR)"
    if cxx is None:
        return None, "no C++ compiler"
    out = os.path.join(workdir, "robot_cpp")
    cmd = [cxx, "-O3", "-DNDEBUG", "-std=c++17",
           "-DBOOST_MPL_LIMIT_LIST_SIZE=30", "-DBOOST_MPL_LIMIT_VECTOR_SIZE=30",
           "-DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS", "-DBOOST_FUSION_INVOKE_MAX_ARITY=12",
           "-DPINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION",
           "-I" + os.path.join(prefix, "include"), "-I" + eigen,
           os.path.join(HERE, "robot_cpp.cpp"), "-o", out,
           "-L" + os.path.join(prefix, "lib"), "-lpinocchio_default", "-lboost_serialization",
           "-Wl,-rpath," + os.path.join(prefix, "lib")]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        return None, "C++ build failed: " + r.stderr.strip().splitlines()[-1]
    return out, None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--configs", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=30)
    ap.add_argument("--chunk", type=int, default=100)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()

    import jvrc_description
    urdf = jvrc_description.urdf_path
    full = pin.buildModelFromUrdf(urdf, pin.JointModelFreeFlyer())
    model = pin.buildReducedModel(full, [full.getJointId(n) for n in FINGERS], pin.neutral(full))
    data = model.createData()
    rng = np.random.default_rng(args.seed)
    qs = [random_configuration(model, rng) for _ in range(args.configs)]
    vs = [rng.normal(size=model.nv) for _ in range(args.configs)]
    v0 = np.zeros(model.nv)
    print(f"JVRC-1 (jvrc-description {jvrc_description.__version__}), fingers locked: "
          f"nq={model.nq}, nv={model.nv}; {args.configs} configurations, {args.repeat} rounds in "
          f"chunks of {args.chunk}; Pinocchio {pin.__version__}, NumPy {np.__version__}")

    work = tempfile.mkdtemp(prefix="stance-robot-bench-")
    try:
        # stance-robot, release build of the runner
        subprocess.run(["cargo", "build", "--release", "--quiet", "-p", "stance-robot",
                        "--example", "bench_centroidal"], cwd=ROOT, check=True)
        runner = os.path.join(ROOT, "target", "release", "examples", "bench_centroidal")
        inp, outp = os.path.join(work, "in.json"), os.path.join(work, "out.json")
        with open(inp, "w") as f:
            json.dump({"urdf": urdf, "locked": [[n, 0.0] for n in FINGERS],
                       "configurations": [q.tolist() for q in qs],
                       "velocities": [v.tolist() for v in vs], "repeat": args.repeat,
                       "chunk": args.chunk}, f)
        subprocess.run([runner, inp, outp], check=True)
        with open(outp) as f:
            rust = json.load(f)

        # values first: every configuration, CoM and A_g
        worst = 0.0
        for q, res in zip(qs, rust["results"]):
            ag = pin.ccrba(model, data, q, v0)
            worst = max(worst, rel_diff(res["com"], data.com[0]), rel_diff(res["centroidal_map"], ag))
        for q, v, dh in zip(qs, vs, rust["centroidal_map_dot_v"]):
            pin.computeCentroidalMomentumTimeVariation(model, data, q, v, v0)
            ref = np.concatenate([data.dhg.linear, data.dhg.angular])
            worst = max(worst, rel_diff(dh, ref))
        if worst > REL_TOL:
            sys.exit(f"answers differ: max relative difference {worst:.2e} > {REL_TOL}")
        print(f"values (CoM, A_g, dA_g/dt v) agree on all {args.configs} configurations: "
              f"max relative difference {worst:.1e}")

        # Pinocchio from Python: one ccrba call per configuration (forward kinematics, CoM, A_g)
        def py_ccrba(part):
            for q in part:
                pin.ccrba(model, data, q, v0)

        def py_three_calls(part):
            for q in part:
                pin.forwardKinematics(model, data, q)
                pin.centerOfMass(model, data, q)
                pin.ccrba(model, data, q, v0)

        def py_trivial(part):
            for q in part:
                pin.isNormalized(model, q)

        pairs = list(zip(qs, vs))

        def py_dot_v(part):
            for q, v in part:
                pin.ccrba(model, data, q, v)
                pin.computeCentroidalMomentumTimeVariation(model, data, q, v, v0)

        t_py = per_config_times(py_ccrba, qs, args.repeat, args.chunk)
        t_py_dot = per_config_times(py_dot_v, pairs, args.repeat, args.chunk)
        t_py3 = per_config_times(py_three_calls, qs, args.repeat, args.chunk)
        t_trivial = per_config_times(py_trivial, qs, args.repeat, args.chunk)

        # Pinocchio's own C++ on the same model (saved from Python) and configurations
        cpp, why = build_cpp(work)
        t_cpp = t_cpp_dot = None
        if cpp:
            model_bin = os.path.join(work, "model.bin")
            model.saveToBinary(model_bin)
            cfg = os.path.join(work, "configs.txt")
            with open(cfg, "w") as f:
                f.write(f"{len(qs)} {model.nq}\n")
                for q in qs:
                    f.write(" ".join(repr(float(x)) for x in q) + "\n")
            vel = os.path.join(work, "velocities.txt")
            with open(vel, "w") as f:
                f.write(f"{len(vs)} {model.nv}\n")
                for v in vs:
                    f.write(" ".join(repr(float(x)) for x in v) + "\n")
            r = subprocess.run([cpp, model_bin, cfg, vel, str(args.repeat), str(args.chunk)],
                               capture_output=True, text=True, check=True)
            lines = r.stdout.strip().splitlines()
            t_cpp = [float(x) for x in lines[0].split()[:2]]
            t_cpp_dot = [float(x) for x in lines[1].split()[:2]]
            com0 = [float(x) for x in lines[2].split()]
            ag0 = [[float(x) for x in line.split()] for line in lines[3:9]]
            dh0 = [float(x) for x in lines[9].split()]
            d = max(rel_diff(com0, rust["results"][0]["com"]),
                    rel_diff(ag0, rust["results"][0]["centroidal_map"]),
                    rel_diff(dh0, rust["centroidal_map_dot_v"][0]))
            if d > REL_TOL:
                sys.exit(f"C++ answer differs: {d:.2e}")
        else:
            print(f"Pinocchio C++: not measured ({why})")

        t_rs = [rust["median_ns"], rust["min_ns"]]
        rows = [("stance-robot (Rust, centroidal_map: FK + CoM + J_com + A_g)", t_rs)]
        if t_cpp is not None:
            rows.append(("Pinocchio C++ (ccrba: FK + CoM + A_g), measured", t_cpp))
        rows.append(("Pinocchio C++ estimate = Python ccrba - trivial call",
                     [a - b for a, b in zip(t_py, t_trivial)]))
        rows.append(("Pinocchio from Python (ccrba per configuration)", t_py))
        rows.append(("Pinocchio from Python (forwardKinematics + centerOfMass + ccrba)", t_py3))
        rows.append(("  trivial binding call (isNormalized(model, q)), for the estimate", t_trivial))
        print("\nFK + CoM + A_g: ns per configuration (median and minimum over the timed chunks); "
              "ratio = side / stance")
        print(f"{'side':<68} {'median':>7} {'ratio':>6} {'min':>7} {'ratio':>6}")
        for name, t in rows:
            print(f"{name:<68} {t[0]:>7.0f} {t[0] / t_rs[0]:>5.2f}x {t[1]:>7.0f} {t[1] / t_rs[1]:>5.2f}x")
        t_rs_dot = [rust["dot_v_median_ns"], rust["dot_v_min_ns"]]
        rows = [("stance-robot (Rust, centroidal_map_dot_v: A_g, J_com, dA_g/dt v)", t_rs_dot)]
        if t_cpp_dot is not None:
            rows.append(("Pinocchio C++ (ccrba + computeCentroidalMomentumTimeVariation)", t_cpp_dot))
        rows.append(("Pinocchio from Python (the same two calls)", t_py_dot))
        print("\nA_g and dA_g/dt v at (q, v), the path terms' kernel: ns per configuration")
        print(f"{'side':<68} {'median':>7} {'ratio':>6} {'min':>7} {'ratio':>6}")
        for name, t in rows:
            print(f"{name:<68} {t[0]:>7.0f} {t[0] / t_rs_dot[0]:>5.2f}x {t[1]:>7.0f} "
                  f"{t[1] / t_rs_dot[1]:>5.2f}x")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
