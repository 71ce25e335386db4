#!/usr/bin/env bash
# Checks that no layer includes a header of a layer above it:
#   model < elements < assembly < solver < analysis < io, plot < the command, the bindings
# (src/tolerances.hpp and the generated stiffmsa/config.hpp sit below them all). The public
# headers (include/stiffmsa/) belong to the layer that implements them. Lists every offending
# include as FILE:LINE and exits non-zero if there is one; a public header that no layer claims
# is one too, so that a new header is placed when it is added. Run by ctest (layer_includes).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
directories=(src include app python/src)
existing=()
for d in "${directories[@]}"; do [[ -d "$d" ]] && existing+=("$d"); done
grep -rn --include='*.hpp' --include='*.cpp' -E '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' \
  "${existing[@]}" | sort | awk '
# The rank of a header as an include names it (relative to src/ or include/), or of a file by
# its path; -1: none known.
function rank_of(path) {
  if (path ~ /^tolerances\.hpp$/ || path ~ /^stiffmsa\/config\.hpp$/) return 0
  if (path ~ /^model\//) return 1
  if (path ~ /^stiffmsa\/(types|errors|number_text|model|structure|validate|parametric)\.hpp$/)
    return 1
  if (path ~ /^elements\//) return 2
  if (path ~ /^assembly\//) return 3
  if (path ~ /^solver\//) return 4
  if (path ~ /^stiffmsa\/solver_kind\.hpp$/) return 4
  if (path ~ /^analysis\//) return 5
  if (path ~ /^stiffmsa\/(analysis|result|sweep|deformed_shape)\.hpp$/) return 5
  if (path ~ /^(io|plot)\//) return 6
  if (path ~ /^stiffmsa\/io\/[a-z_0-9]+\.hpp$/) return 6
  if (path ~ /^stiffmsa\/stiffmsa\.hpp$/) return 7
  return -1
}
BEGIN {
  name[0] = "base"; name[1] = "model"; name[2] = "elements"; name[3] = "assembly"
  name[4] = "solver"; name[5] = "analysis"; name[6] = "io/plot"; name[7] = "front end"
  bad = 0
}
{
  file = $0; sub(/:.*/, "", file)
  rest = substr($0, length(file) + 2)
  line = rest; sub(/:.*/, "", line)
  header = rest; sub(/^[^"]*"/, "", header); sub(/".*/, "", header)
  if (file ~ /^(app|python\/src)\//) from = 7
  else if (file ~ /^src\//) from = rank_of(substr(file, 5))
  else from = rank_of(substr(file, 9))  # include/
  if (file ~ /^src\/tolerances\.hpp$/) from = 0
  if (from < 0) {
    printf "%s: no layer claims this file (scripts/check-layers.sh)\n", file
    bad = 1
    next
  }
  to = rank_of(header)
  if (to < 0) {
    # A header beside the file (the command'"'"'s own), or a public header no layer claims.
    if (header ~ /^stiffmsa\//) {
      printf "%s:%s: \"%s\" belongs to no layer (scripts/check-layers.sh)\n", file, line, header
      bad = 1
    }
    next
  }
  if (to > from) {
    printf "%s:%s: the %s layer includes \"%s\" of the %s layer above it\n", file, line,
           name[from], header, name[to]
    bad = 1
  }
}
END { exit bad }
' && echo "check-layers: no layer includes a header of a layer above it" || {
  echo "check-layers: move the type down or the code up" >&2
  exit 1
}
