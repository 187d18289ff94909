#!/usr/bin/env bash
# Builds the Python package (crates/stance-py, with maturin from PyPI) into the project
# virtualenv, checks its Rust side (fmt, clippy, doc), its stubs against the module (mypy's
# stubtest) and its Python side (mypy --strict), and runs its tests (pytest). Run
# scripts/setup-venv.sh (--peers for the live comparisons with the peers) first.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
venv="${STANCE_VENV:-$root/.venv}"
py="$venv/bin/python"
pkg="$root/crates/stance-py"
pip=("$py" -m pip install --quiet --disable-pip-version-check)

echo "-- stance-py: fmt, clippy, doc"
export PYO3_PYTHON="$py"
# The checks share the workspace's target folder: its clippy and doc runs have already checked
# every dependency the bindings share with it (the wheel below builds in the package's own).
check_dir="${CARGO_TARGET_DIR:-$root/target}"
cargo fmt --manifest-path "$pkg/Cargo.toml" -- --check
CARGO_TARGET_DIR="$check_dir" cargo clippy --manifest-path "$pkg/Cargo.toml" --all-targets -- -D warnings
CARGO_TARGET_DIR="$check_dir" RUSTDOCFLAGS="-D warnings" \
    cargo doc --manifest-path "$pkg/Cargo.toml" --no-deps
echo "-- stance-py: wheel into $venv"
"${pip[@]}" -r "$pkg/requirements-test.txt"
"${pip[@]}" --force-reinstall --no-deps "$pkg"
echo "-- stance-py: stubs against the module, types"
# Outside the repository, so that `stance` is the installed package.
(cd "$(mktemp -d)" && "$py" -m mypy.stubtest stance && "$py" -m mypy --strict -p stance)
echo "-- stance-py: tests"
"$py" -m pytest -q "$pkg/tests"
# The goldens the Rust tests compare with, recomputed with the peers that made them.
if "$py" -c "import cdd, toppra, scipy" 2>/dev/null; then
  for g in cones topp; do
    echo "-- goldens: testdata/$g"
    "$py" "$root/testdata/$g/regenerate.py" --check
  done
else
  echo "-- goldens: not checked (no pycddlib/toppra: scripts/setup-venv.sh --peers)"
fi
