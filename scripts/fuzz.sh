#!/usr/bin/env bash
# Builds the libFuzzer target of the model loader (clang, with AddressSanitizer and
# UndefinedBehaviorSanitizer) in build-fuzz and runs it for a bounded time from the seed corpus
# fuzz/seeds (and tests/invalid when it exists). Prints the number of inputs executed; fails on
# any crash, sanitizer report, uncaught exception, timeout or out-of-memory, whose input is kept
# in build-fuzz/artifacts/. Works from any directory; installs the Debian packages it needs.
#   usage: scripts/fuzz.sh [SECONDS]        (default: $FUZZ_SECONDS, else 60)
#   reproduce a finding: build-fuzz/fuzz/model_loader_fuzzer build-fuzz/artifacts/crash-...
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="build-fuzz"
seconds="${1:-${FUZZ_SECONDS:-60}}"
case "$seconds" in
  '' | *[!0-9]*) echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2; exit 2 ;;
esac

bash scripts/install-deps.sh fuzz
cxx=clang++-14
command -v "$cxx" >/dev/null || cxx=clang++

source scripts/build-cache.sh
# RelWithDebInfo: fast executions with line numbers in the stacks (assertions off, as shipped).
cmake -S . -B "$build" -G Ninja "${compiler_launcher[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER="$cxx" \
  -DSTIFFMSA_SANITIZE=address,undefined -DSTIFFMSA_BUILD_FUZZERS=ON \
  -DSTIFFMSA_BUILD_TESTS=OFF -DSTIFFMSA_BUILD_EXAMPLES=OFF
cmake --build "$build" -j2 --target model_loader_fuzzer

# New inputs go to build-fuzz/corpus (the first directory); the seeds are only read.
corpus_dirs=("$build/corpus" fuzz/seeds)
[ -d tests/invalid ] && corpus_dirs+=(tests/invalid)
mkdir -p "$build/corpus" "$build/artifacts"
log="$build/fuzz.log"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:print_stacktrace=1"
# Leaks inside third-party libraries that no caller can free: the list sanitize.sh uses.
export LSAN_OPTIONS="suppressions=$root/scripts/lsan-suppressions.txt:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"

echo "fuzz.sh: fuzzing the model loader for ${seconds} s (corpus: ${corpus_dirs[*]})"
status=0
"$build/fuzz/model_loader_fuzzer" \
  -max_total_time="$seconds" -max_len=16384 -timeout=10 -rss_limit_mb=2048 \
  -malloc_limit_mb=1024 -dict=fuzz/model.dict -print_final_stats=1 \
  -artifact_prefix="$build/artifacts/" \
  "${corpus_dirs[@]}" >"$log" 2>&1 || status=$?

runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
if [ "$status" -ne 0 ]; then
  # libFuzzer's report: the sanitizer's or its own, with the stack and the artifact's name.
  grep -v -E '^#[0-9]+\s+(NEW|REDUCE|pulse|RELOAD)' "$log" | tail -n 80 >&2
  echo "fuzz.sh: FAILED after ${runs:-?} executions (exit $status); the input is in" \
       "$build/artifacts/, full log in $log" >&2
  exit 1
fi
tail -n 12 "$log"
echo "fuzz.sh: ${runs:-?} inputs executed in ${seconds} s without a crash" \
     "(corpus $(find "$build/corpus" -type f | wc -l) files)"
