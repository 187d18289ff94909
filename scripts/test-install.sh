#!/usr/bin/env bash
# The binary works wherever it is installed: `cargo install` into a fresh folder, then, from
# another folder and with no source tree in sight, `stance simulate small-sway` and `stance view
# box-climbing`, first with STANCE_VENV set (the source tree's virtualenv), then with the
# per-user default that `stance setup` creates (a fresh HOME; pip reuses the wheels already
# downloaded, if any, from the usual cache).
#
# Usage: bash scripts/test-install.sh [--release]   (default: the dev profile, which reuses the
# test build's artifacts; --release is what `cargo install` does by default)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
profile=(--debug)
[ "${1:-}" = "--release" ] && profile=()
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
pip_cache="${PIP_CACHE_DIR:-$HOME/.cache/pip}"

echo "install: cargo install ${profile[*]} --path crates/stance-cli --root $work/prefix"
CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}" \
  cargo install --quiet --locked "${profile[@]}" --path "$root/crates/stance-cli" --root "$work/prefix"
stance="$work/prefix/bin/stance"
mkdir -p "$work/elsewhere"
cd "$work/elsewhere"

check_simulate() {
  "$stance" simulate small-sway -o report.json
  python3 -c 'import json,sys; r=json.load(open("report.json")); sys.exit(0 if r["held"] else "small-sway did not hold: " + str(r["reason"]))'
}
check_view() {
  "$stance" view box-climbing -o box.html
  python3 -c 'import sys; t=open("box.html").read(); sys.exit(0 if "stance-data" in t and len(t) > 100000 else "box.html is not a page")'
}

echo "1. STANCE_VENV=$root/.venv, from $work/elsewhere"
STANCE_VENV="$root/.venv" check_simulate
STANCE_VENV="$root/.venv" check_view

echo "2. the per-user default (a fresh HOME): stance setup, then the same commands"
export HOME="$work/home"
unset STANCE_VENV XDG_DATA_HOME
mkdir -p "$HOME"
"$stance" setup --check | grep -q "missing" || { echo "a fresh HOME should have no virtualenv"; exit 1; }
PIP_CACHE_DIR="$pip_cache" "$stance" setup
"$stance" setup --check | grep -q "(ready)"
[ -x "$HOME/.local/share/stance/.venv/bin/python" ] || { echo "no per-user virtualenv"; exit 1; }
check_simulate
check_view
echo "install anywhere: ok"
