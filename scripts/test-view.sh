#!/usr/bin/env bash
# The browser test of `stance view` (issue 16): installs headless Chromium (Debian's
# chromium-headless-shell) when it is missing, builds the command line, and runs
# scripts/test_view.py. Pass --update-docs to refresh the reference screenshots in docs/.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v chromium-headless-shell >/dev/null && ! command -v chromium >/dev/null; then
  echo "== installing chromium-headless-shell (Debian package)"
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends \
    chromium-headless-shell fonts-dejavu-core
fi
cargo build -q -p stance-cli
export STANCE_VENV="${STANCE_VENV:-$PWD/.venv}"
PY="$PWD/.venv/bin/python"
if [ ! -x "$PY" ]; then PY=python3; fi
"$PY" scripts/test_view.py target/debug/stance "$@"
