#!/usr/bin/env bash
# Builds stiffmsa with its tests and runs every test. Works from any directory; installs the
# Debian packages it needs first (as root, or through sudo).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

bash scripts/install-deps.sh
# With MPI and HDF5, so that the tests cover sweeps over ranks and HDF5 rows (docs/cluster.md).
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSTIFFMSA_WITH_MPI=ON -DSTIFFMSA_WITH_HDF5=ON
cmake --build build -j2
ctest --test-dir build --output-on-failure
