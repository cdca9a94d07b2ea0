#!/usr/bin/env bash
# Lists the functions longer than LIMIT lines (default 150) and the source files longer than
# FILE_LIMIT lines (default 600) in the project's code folders, from universal-ctags' end lines.
# --check exits 1 when any is found. Usage: scripts/long_functions.sh [--check] [LIMIT [FILE_LIMIT]]
set -euo pipefail
cd "$(dirname "$0")/.."
check=0; [ "${1:-}" = --check ] && { check=1; shift; }
limit=${1:-150}; file_limit=${2:-600}
command -v ctags >/dev/null || { echo "long_functions.sh: needs universal-ctags (apt-get install universal-ctags)" >&2; exit 2; }
folders=(src cli device qt_ui vtk_pipelines report peers python paraview)
files=$(find "${folders[@]}" -type f \( -name '*.cpp' -o -name '*.cxx' -o -name '*.h' \) | sort)
found=0
while read -r lines file; do
  [ "$file" = total ] && continue
  if [ "$lines" -gt "$file_limit" ]; then echo "file $file: $lines lines"; found=1; fi
done < <(echo "$files" | xargs wc -l)
# ctags -x with line and end: one function definition a row.
out=$(echo "$files" | ctags -L - --languages=C++ --kinds-C++=f --fields=+ne -o - 2>/dev/null |
  awk -F'\t' -v limit="$limit" '{ line=""; end="";
      for (i = 4; i <= NF; i++) { if ($i ~ /^line:/) line = substr($i, 6); if ($i ~ /^end:/) end = substr($i, 5) }
      if (line != "" && end != "" && end - line + 1 > limit) printf "function %s:%s %s: %d lines\n", $2, line, $1, end - line + 1 }')
[ -n "$out" ] && { echo "$out"; found=1; }
[ $check = 1 ] && [ $found = 1 ] && exit 1
exit 0
