#!/usr/bin/env bash
# Builds stiffmsa and every test with AddressSanitizer (leaks included) and
# UndefinedBehaviorSanitizer (g++, -O1 -g, assertions on) in build-asan, and runs the test suite.
# Fails on any failing test and on any sanitizer report, also one from a process a test starts
# (the stiffmsa command run by test_cli). Works from any directory; installs the Debian packages
# it needs first (as root, or through sudo).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="build-asan"

bash scripts/install-deps.sh sanitize

# Every report goes to a file named after the process, so that none is lost when a test reads
# the output or the exit code of a command it runs; exit code 86 keeps a sanitizer failure apart
# from the command's own exit codes (1, 2).
logs="$root/$build/sanitizer-logs"
rm -rf "$logs"
mkdir -p "$logs"
common="halt_on_error=1:exitcode=86:print_stacktrace=1:log_path=$logs/report"
export ASAN_OPTIONS="$common:detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1:strict_string_checks=1"
export UBSAN_OPTIONS="$common"
# print_suppressions=0: the count of suppressed leaks would otherwise be a report file of its own.
export LSAN_OPTIONS="$common:suppressions=$root/scripts/lsan-suppressions.txt:print_suppressions=0"

# Debug with -O1: sanitizers at a bearable speed, with assert(), Eigen's index checks and
# libstdc++'s container checks switched on. Linked by lld (install-deps.sh, `sanitize`): the
# default linker took ~15 s for each of the ~35 programs, lld ~4.5 s.
source scripts/build-cache.sh
cmake -S . -B "$build" -G Ninja "${compiler_launcher[@]}" -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_COMPILER=g++ \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g -D_GLIBCXX_ASSERTIONS" \
  -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld -DCMAKE_SHARED_LINKER_FLAGS=-fuse-ld=lld \
  -DCMAKE_MODULE_LINKER_FLAGS=-fuse-ld=lld \
  -DSTIFFMSA_SANITIZE=address,undefined \
  -DSTIFFMSA_BUILD_TESTS=ON -DSTIFFMSA_BUILD_EXAMPLES=ON
cmake --build "$build" -j2

status=0
# Tests that bound their own processor time hold optimised-build limits (scripts/test.sh holds
# them); under AddressSanitizer, whose allocator alone makes loading several times slower, they
# cannot. They run here too, for the sanitizers: a report from them fails this script like any
# other, only their time bound is not held against them.
timed='^Limits\.ChainOf100000LinksLoadsQuickly$'
# The viewer's pages in a browser are checked once, by scripts/test.sh: a browser run here would
# test Chromium, not our code under the sanitizers (the command that writes the pages runs here
# through the C++ tests).
browser='^viewer_browser$'
ctest --test-dir "$build" --output-on-failure -j2 -E "$timed|$browser" || status=$?
ctest --test-dir "$build" --output-on-failure -R "$timed" ||
  echo "sanitize.sh: note: a timed test missed its time bound (expected under the sanitizers);" \
       "only a sanitizer report from it counts here" >&2
# The API example, under the sanitizers too.
"$build/api_example" >/dev/null || status=$?

reports=$(find "$logs" -type f -size +0 | sort)
if [ -n "$reports" ]; then
  echo "sanitize.sh: sanitizer reports:" >&2
  for f in $reports; do
    echo "---- $f" >&2
    cat "$f" >&2
  done
  status=1
fi
if [ "$status" -ne 0 ]; then
  echo "sanitize.sh: FAILED (tests or sanitizer reports above)" >&2
  exit "$status"
fi
echo "sanitize.sh: every test passed under AddressSanitizer and UndefinedBehaviorSanitizer" \
     "(time bounds of the timed tests aside), no sanitizer report"
