#!/usr/bin/env bash
# Builds stiffmsa with its tests and runs every test. Works from any directory; installs the
# Debian packages it needs first (as root, or through sudo).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

bash scripts/install-deps.sh viewer
source scripts/build-cache.sh
cmake -S . -B build -G Ninja "${compiler_launcher[@]}" -DCMAKE_BUILD_TYPE=Release
cmake --build build -j2
ctest --test-dir build --output-on-failure
