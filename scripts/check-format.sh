#!/usr/bin/env bash
# Checks that the C++ sources follow .clang-format (Google's style, 100 columns): lists every
# file clang-format would change and exits non-zero if there is one. Changes nothing; to
# reformat a file, run `clang-format -i FILE`. CLANG_FORMAT picks the binary (default
# clang-format).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
clang_format="${CLANG_FORMAT:-clang-format}"
if ! command -v "$clang_format" >/dev/null; then
  echo "check-format: $clang_format not found (Debian: apt-get install clang-format)" >&2
  exit 2
fi
directories=(src include app tests python/src bench fuzz examples)
existing=()
for d in "${directories[@]}"; do [[ -d "$d" ]] && existing+=("$d"); done
mapfile -d '' files < <(find "${existing[@]}" -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.cc' \) -print0 |
  sort -z)
if ((${#files[@]} == 0)); then
  echo "check-format: no C++ files found" >&2
  exit 2
fi
if "$clang_format" --dry-run -Werror "${files[@]}"; then
  echo "check-format: ${#files[@]} files follow .clang-format"
else
  echo "check-format: the files above differ from .clang-format; run clang-format -i on them" >&2
  exit 1
fi
