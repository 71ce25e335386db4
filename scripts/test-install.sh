#!/usr/bin/env bash
# The installed package as a user meets it: `cmake --install` of a build into a temporary prefix,
# then tests/consumer (a separate project: find_package(stiffmsa 0.2 COMPONENTS core) and
# stiffmsa::core) configured, built and run against it. Also checks that the consumer of the
# core links none of the other layers' libraries. Usage: scripts/test-install.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
source "$root/scripts/build-cache.sh"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$root/tests/consumer" -B "$work/consumer" -G Ninja "${compiler_launcher[@]}" \
      -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/consumer" >/dev/null
"$work/consumer/cantilever"

# What the core's consumer loads: none of cairo, libfyaml, muparser, oneTBB.
needed="$(readelf -d "$work/consumer/cantilever" | grep NEEDED || true)"
for library in cairo fyaml muparser tbb; do
  if grep -q "$library" <<<"$needed"; then
    echo "test-install: the core's consumer links $library:" >&2
    echo "$needed" >&2
    exit 1
  fi
done
echo "test-install: the installed package builds and runs tests/consumer (stiffmsa::core alone)"
