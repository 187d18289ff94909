#!/usr/bin/env bash
# Creates the project's Python virtualenv (default: .venv at the project root; override with
# STANCE_VENV) and installs into it, from PyPI:
#   always:   bench/peers/requirements-tests.txt: jvrc-description (the JVRC-1 humanoid URDF,
#             used by stance-robot's tests) and mujoco (`stance simulate` and its tests)
#   --peers:  the peers used as black-box oracles by bench/peers/ and the fixture scripts
#             (pycddlib, pypoman, toppra, Pinocchio, NumPy, SciPy; example-robot-data's UR5, Panda
#             and Talos URDFs), and the Debian packages
#             they build against (cddlib, GMP, Eigen headers; needs root for apt-get)
# Idempotent: re-running it only installs what is missing.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
venv="${STANCE_VENV:-$root/.venv}"
python="${PYTHON:-python3}"
[ -x "$venv/bin/python" ] || "$python" -m venv "$venv"
pip=("$venv/bin/python" -m pip install --quiet --disable-pip-version-check)
"${pip[@]}" -r "$root/bench/peers/requirements-tests.txt"
if [ "${1:-}" = "--peers" ]; then
  # pycddlib builds against the system's cddlib and GMP headers, and the C++ side of
  # bench/peers/robot.py compiles against Pinocchio's headers, which need Eigen's (Debian packages).
  if { ! [ -f /usr/include/cddlib/setoper.h ] || ! [ -d /usr/include/eigen3 ]; } \
      && command -v apt-get >/dev/null; then
    apt-get update -qq && apt-get install -y -qq libcdd-dev libgmp-dev libeigen3-dev g++ >/dev/null
  fi
  "${pip[@]}" -r "$root/bench/peers/requirements-peers.txt"
fi
echo "virtualenv ready: $venv"
