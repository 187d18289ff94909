#!/usr/bin/env bash
# Regenerates crates/stance-view/assets/view/three.min.js, the one copy of three.js (MIT) that
# `stance view` inlines into its pages: the names listed in three-entry.js, bundled by esbuild
# into a classic script defining the global THREE, with three.js's license as its header.
# Needs node and npm (packages from the npm registry); not needed to build or test stance.
set -euo pipefail
THREE_VERSION=0.187.0
ESBUILD_VERSION=0.25.12
here="$(cd "$(dirname "$0")/.." && pwd)"
out="$here/crates/stance-view/assets/view/three.min.js"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
npm init -y >/dev/null
npm install --silent --no-audit --no-fund "three@$THREE_VERSION" "esbuild@$ESBUILD_VERSION"
cp "$here/crates/stance-view/assets/view/three-entry.js" entry.js
{
  echo "/* three.js $THREE_VERSION (https://threejs.org), bundled for stance by scripts/vendor-three.sh"
  echo "   (esbuild $ESBUILD_VERSION, names in three-entry.js). Its license:"
  echo
  sed 's/^/   /' node_modules/three/LICENSE
  echo "*/"
  node_modules/.bin/esbuild entry.js --bundle --minify --format=iife --global-name=THREE \
    --legal-comments=none --target=es2019
} > "$out"
echo "wrote $out ($(wc -c < "$out") bytes)"
