#!/usr/bin/env bash
# Builds stiffmsa with its tests and runs every test. Works from any directory; installs the
# Debian packages it needs first (as root, or through sudo).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

bash scripts/install-deps.sh viewer python
source scripts/build-cache.sh
# With MPI and HDF5, so that the tests cover sweeps over ranks and HDF5 rows (docs/cluster.md).
cmake -S . -B build -G Ninja "${compiler_launcher[@]}" -DCMAKE_BUILD_TYPE=Release -DSTIFFMSA_WITH_MPI=ON -DSTIFFMSA_WITH_HDF5=ON
cmake --build build -j2
ctest --test-dir build --output-on-failure
# The installed CMake package from a separate project (tests/consumer; docs/library.md).
bash scripts/test-install.sh build

# The Python package, installed as the README shows (offline: Debian's build tools, no index),
# and its tests against the command just built. pytest's exit code 5 (no tests ran) fails too.
/usr/bin/python3 -m venv --system-site-packages .venv
PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 .venv/bin/pip install --quiet --no-build-isolation .
STIFFMSA_CLI="$root/build/stiffmsa" .venv/bin/python -m pytest -q -p no:cacheprovider tests/python
