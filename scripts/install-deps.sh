#!/usr/bin/env bash
# Installs the Debian packages stiffmsa builds with. Safe to run again; needs root (or sudo).
#   usage: scripts/install-deps.sh [fuzz] [bench] [viewer] [python] [sanitize]
# With `bench`, also Google Benchmark, valgrind (instruction counts) and GNU time (bench/run.sh,
# bench/compare.sh, bench/pose_loop.cpp under callgrind); perf for bench/profile.py is not included.
# With `fuzz`, also clang and its sanitizer and libFuzzer runtimes (scripts/fuzz.sh). The
# sanitizer build with g++ (scripts/sanitize.sh) takes `sanitize`: g++ brings libasan and
# libubsan, and LLVM's linker, lld, links its tests (each against a library of ~800 MB with its
# debug information) three times faster than the default linker.
# With `python`, also what the Python package builds and tests with, Debian's own (pip installs
# it offline: --no-build-isolation, see docs/python.md): pybind11, numpy, venv, pip, wheel,
# setuptools, pytest, and matplotlib and pandas for the examples.
set -euo pipefail
# libopenblas0-serial: CHOLMOD's supernodal Cholesky (the frame solve) spends its time in BLAS,
# which Debian otherwise provides as the unoptimised reference BLAS (the 960-beam frame: 22 ms
# against 12 ms); serial, so that BLAS starts no threads of its own beside the caller's.
packages=(cmake ninja-build g++ libeigen3-dev libfyaml-dev nlohmann-json3-dev libcli11-dev
          libsuitesparse-dev libopenblas0-serial libmuparser-dev libtbb-dev libcairo2-dev pkg-config
          libgtest-dev libgmock-dev ccache clang-format
          liburdfdom-dev liburdfdom-headers-dev libtinyxml-dev libconsole-bridge-dev)
# libjs-three: three.js r111 (Debian 12's 111+dfsg1-3), built into the viewer's pages.
packages+=(libjs-three)
# Sweeps beyond one machine (docs/cluster.md): HDF5 output, MPI ranks, and h5py and pandas to
# check the HDF5 file in tests/test_sweep_scale.cpp.
packages+=(libhdf5-dev openmpi-bin libopenmpi-dev python3-h5py python3-pandas)
for group in "$@"; do
  case "$group" in
    fuzz) packages+=(clang-14 libclang-rt-14-dev) ;;
    sanitize) packages+=(lld) ;;
    bench) packages+=(libbenchmark-dev valgrind time python3) ;;
    # The viewer's tests: its pages in headless Chromium, its ParaView files read by meshio.
    viewer) packages+=(chromium python3 python3-meshio python3-numpy) ;;
    python) packages+=(python3-dev pybind11-dev python3-pybind11 python3-numpy python3-venv python3-pip
                       python3-wheel python3-setuptools python3-pytest python3-matplotlib python3-pandas) ;;
    *) echo "install-deps.sh: unknown group '$group' (known: fuzz, bench, viewer, python, sanitize)" >&2; exit 2 ;;
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
