#!/usr/bin/env bash
# Installs the Debian packages stiffmsa builds with. Safe to run again; needs root (or sudo).
#   usage: scripts/install-deps.sh [fuzz] [bench]
# With `bench`, also Google Benchmark, valgrind (instruction counts) and GNU time (bench/run.sh,
# bench/compare.sh, bench/pose_loop.cpp under callgrind); perf for bench/profile.py is not included.
# With `fuzz`, also clang and its sanitizer and libFuzzer runtimes (scripts/fuzz.sh). The
# sanitizer build with g++ (scripts/sanitize.sh) needs nothing more: g++ brings libasan and
# libubsan.
set -euo pipefail
# libopenblas0-serial: CHOLMOD's supernodal Cholesky (the frame solve) spends its time in BLAS,
# which Debian otherwise provides as the unoptimised reference BLAS (the 960-beam frame: 22 ms
# against 12 ms); serial, so that BLAS starts no threads of its own beside the caller's.
packages=(cmake ninja-build g++ libeigen3-dev libfyaml-dev nlohmann-json3-dev libcli11-dev
          libsuitesparse-dev libopenblas0-serial libmuparser-dev libtbb-dev libcairo2-dev pkg-config
          libgtest-dev libgmock-dev)
# Sweeps beyond one machine (docs/cluster.md): HDF5 output, MPI ranks, and h5py and pandas to
# check the HDF5 file in tests/test_sweep_scale.cpp.
packages+=(libhdf5-dev openmpi-bin libopenmpi-dev python3-h5py python3-pandas)
for group in "$@"; do
  case "$group" in
    fuzz) packages+=(clang-14 libclang-rt-14-dev) ;;
    bench) packages+=(libbenchmark-dev valgrind time python3) ;;
    *) echo "install-deps.sh: unknown group '$group' (known: fuzz, bench)" >&2; exit 2 ;;
  esac
done
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
sudo_cmd=""
[ "$(id -u)" -eq 0 ] || sudo_cmd="sudo"
echo "installing: ${missing[*]}" >&2
$sudo_cmd apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
