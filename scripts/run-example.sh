#!/usr/bin/env bash
# Builds the stiffmsa command and solves a bundled example, writing its result file next to the
# build. Works from any directory; installs the Debian packages it needs first.
#   usage: scripts/run-example.sh [examples/NAME.yaml]     (default: examples/planar-2r.yaml)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

example="${1:-examples/planar-2r.yaml}"
name="$(basename "${example%.*}")"

bash scripts/install-deps.sh
source scripts/build-cache.sh
cmake -S . -B build -G Ninja "${compiler_launcher[@]}" -DCMAKE_BUILD_TYPE=Release
# Only the command: the example does not need the tests built.
cmake --build build -j2 --target stiffmsa_cli
build/stiffmsa solve "$example" --json "build/${name}-result.json"
