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
# The installed command: the executable finds its command module (and that module the plot and
# HDF5 modules) in the install's library folder, not beside itself; every subcommand runs and
# writes what the build folder's command writes.
installed="$work/prefix/bin/stiffmsa"
built="$build/stiffmsa"
if [[ -x "$installed" ]]; then
  [[ "$("$installed" --version)" == "$("$built" --version)" ]]
  "$installed" --help >/dev/null
  rpr="$root/examples/planar-3rpr-parametric.yaml"
  for run in installed built; do
    command="${!run}"
    out="$work/$run-run"
    mkdir -p "$out"
    "$command" check "$root/examples/industrial-6axis.yaml" >/dev/null
    "$command" solve "$root/examples/industrial-6axis.yaml" --json "$out/6axis.json" >/dev/null
    "$command" expand "$rpr" --set x=0.4 -o "$out/expanded.yaml"
    "$command" view "$root/examples/planar-3rpr.yaml" -o "$out/view.html" >/dev/null
    sweep=("$command" sweep "$rpr" --grid x=0.4:0.5:3 --grid y=0.3:0.35:2 --quiet)
    "${sweep[@]}" --csv "$out/rows.csv" >/dev/null
    "${sweep[@]}" --shard 1/2 --csv "$out/part1.csv" >/dev/null
    "${sweep[@]}" --shard 2/2 --csv "$out/part2.csv" >/dev/null
    "$command" merge "$out/merged.csv" "$out/part1.csv" "$out/part2.csv" >/dev/null
    if [[ -e "$build/stiffmsa_plot.so" ]]; then
      "${sweep[@]}" --csv "$out/plotted.csv" --plot >/dev/null
      ls "$out"/plotted*.png >/dev/null
    fi
    if [[ -e "$build/stiffmsa_hdf5.so" ]]; then
      "${sweep[@]}" --hdf5 "$out/rows.h5" >/dev/null
    fi
    # The MPI module (a build with STIFFMSA_WITH_MPI): two ranks write the rows one process does.
    if [[ -e "$build/stiffmsa_mpi.so" ]]; then
      OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \
        mpirun --oversubscribe -n 2 "${sweep[@]}" --csv "$out/ranks.csv" >/dev/null
      cmp "$out/ranks.csv" "$out/rows.csv"
    fi
  done
  for file in 6axis.json expanded.yaml rows.csv merged.csv; do
    cmp "$work/installed-run/$file" "$work/built-run/$file"
  done
  echo "test-install: the installed command runs every subcommand as the build's does"
fi
echo "test-install: the installed package builds and runs tests/consumer (stiffmsa::core alone)"
