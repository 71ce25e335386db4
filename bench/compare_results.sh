#!/usr/bin/env bash
# Whether two builds write the same result files: `solve --json` of every example, of the
# Frame3DD cases of tests/data/frame3dd, and of the bench's lattice and frames (make_models.py).
#   bench/compare_results.sh BEFORE/stiffmsa AFTER/stiffmsa
set -uo pipefail
before="$1" after="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
python3 "$root/bench/make_models.py" lattice 6 6 7 > "$work/lattice-6-6-7.yaml"
for size in "5 5 10" "10 10 10" "10 10 20"; do
  python3 "$root/bench/make_models.py" frame $size > "$work/frame-${size// /-}.yaml"
done
different=0
for model in "$root"/examples/*.yaml "$root"/tests/data/frame3dd/*.yaml "$work"/*.yaml; do
  name="$(basename "$model" .yaml)"
  "$before" solve "$model" --json "$work/$name.before.json" > /dev/null 2>&1
  status_before=$?
  "$after" solve "$model" --json "$work/$name.after.json" > /dev/null 2>&1
  status_after=$?
  if [[ $status_before != "$status_after" ]]; then
    echo "$name: exit $status_before before, $status_after after"; different=1
  elif [[ ! -e "$work/$name.before.json" ]]; then
    echo "$name: no result (exit $status_before), both"
  elif cmp -s "$work/$name.before.json" "$work/$name.after.json"; then
    echo "$name: the same bytes"
  else
    echo "$name: DIFFERENT"; different=1
  fi
done
exit $different
