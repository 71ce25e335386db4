# Sourced by the build scripts after they set `root`: every build goes through ccache where it is
# installed (scripts/install-deps.sh installs it), so that the builds of one run that compile the
# same sources with the same flags (the tests' build and the Python package's) compile them once,
# and a second run recompiles only what changed. Paths below the repository are hashed relative
# to it, so two clones share their objects. Without ccache the builds are the same, only slower.
export CCACHE_BASEDIR="$root"
export CCACHE_NOHASHDIR=1
compiler_launcher=()
if command -v ccache >/dev/null; then
  compiler_launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
