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
cargo fmt --manifest-path "$pkg/Cargo.toml" -- --check
cargo clippy --manifest-path "$pkg/Cargo.toml" --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --manifest-path "$pkg/Cargo.toml" --no-deps
echo "-- stance-py: wheel into $venv"
"${pip[@]}" -r "$pkg/requirements-test.txt"
"${pip[@]}" --force-reinstall --no-deps "$pkg"
echo "-- stance-py: stubs against the module, types"
# Outside the repository, so that `stance` is the installed package.
(cd "$(mktemp -d)" && "$py" -m mypy.stubtest stance && "$py" -m mypy --strict -p stance)
echo "-- stance-py: tests"
"$py" -m pytest -q "$pkg/tests"
