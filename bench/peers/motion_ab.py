#!/usr/bin/env python3
"""Two or more builds of the whole-body runner side by side, alternating, in rounds: the way to
tell a change of a millisecond from this small shared machine's noise (one binary's median moves
by about 1 ms from one round to the next).

Run from the project root, after copying each build's runner aside, for example

    cargo build --release -p stance-motion --example bench_motion
    cp target/release/examples/bench_motion /tmp/after
    git stash; cargo build --release -p stance-motion --example bench_motion
    cp target/release/examples/bench_motion /tmp/before; git stash pop
    python3 bench/peers/motion_ab.py --rounds 8 --repeat 10 \\
        box-climbing,stair-climbing,small-sway,squat,hand-on-wall /tmp/before /tmp/after

Each round runs every motion with every build (`REPEAT` runs in one process each, the runner's
medians); the table gives, per motion and build, the median over the rounds of `U_stance` + rows
+ TOPP (`t_u_abc_topp_ms`, the issue's figure), the oracle's time in the first solve, the last
solve and the whole pipeline (ms). A build written `BIN:--no-limits` runs without the actuator
limits (`BIN BIN:--no-limits`: their cost, in one run). A motion is a built-in name or a file of `gallery/` (by its
name without `.toml`). JVRC-1 needs the virtualenv (`STANCE_VENV`, default `.venv`).
"""

import argparse
import json
import os
import statistics
import subprocess
import tempfile

KEYS = ["t_u_abc_topp_ms", "t_lifted_ms", "t_topp_ms", "t_pipeline_ms"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=10)
    ap.add_argument("motions", help="comma-separated built-in names or gallery/NAME.toml stems")
    ap.add_argument(
        "builds",
        nargs="+",
        help="runner binaries (bench_motion) to compare; BIN:--no-limits runs BIN without the "
        "actuator limits (the same build with and without them side by side)",
    )
    args = ap.parse_args()
    root = os.getcwd()
    env = dict(os.environ)
    env.setdefault("STANCE_VENV", os.path.join(root, ".venv"))
    found = {}
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run.json")
        for _ in range(args.rounds):
            for m in args.motions.split(","):
                path = os.path.join("gallery", m + ".toml")
                motion = path if os.path.exists(path) else m
                for b in args.builds:
                    binary, _, flag = b.partition(":")
                    # the gallery's Talos motions name their URDF relative to gallery/
                    cwd = "gallery" if motion.startswith("gallery") else root
                    arg = os.path.basename(motion) if cwd == "gallery" else motion
                    subprocess.run(
                        [os.path.abspath(binary), arg, str(args.repeat), out]
                        + ([flag] if flag else []),
                        cwd=cwd,
                        env=env,
                        check=True,
                        capture_output=True,
                    )
                    with open(out) as f:
                        t = json.load(f)["timings"]
                    for k in KEYS:
                        # (a runner older than the actuator limits has no oracle's time)
                        found.setdefault((m, b, k), []).append(t.get(k, float("nan")))
    print("medians over %d rounds of %d runs each (ms)" % (args.rounds, args.repeat))
    for m in args.motions.split(","):
        for b in args.builds:
            cells = " ".join(
                "%s=%.2f" % (k[2:-3], statistics.median(found[(m, b, k)])) for k in KEYS
            )
            print("%-16s %-24s %s" % (m, b, cells))


if __name__ == "__main__":
    main()
