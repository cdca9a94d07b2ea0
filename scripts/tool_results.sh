#!/usr/bin/env bash
# The tool table of the README: each model's default bake, a 2 mm sphere burr of 1,000 points
# along 20 slides (0.5 mm deep, 30 mm/s; 5,000 ticks), box against exact Embree's faster API and
# the distance-field peer at the box file's memory, in one run each (`hapticbox bench --tool`).
#
#   scripts/tool_results.sh [--large] [--no-write]
#
# --large adds the armadillo subdivided to 13M triangles (results.sh makes the same file).
# Writes out/results/tools.md and the README's block between the tools markers.
# HB_TABLE_ONLY=1 makes the table again from the last run's out/results/tool_*.json.
set -euo pipefail
cd "$(dirname "$0")/.."
HB=${HB:-build/cli/hapticbox}
models=(armadillo fandisk chess_piece bumpy_sphere femur_bone bull blade armadillo_832k)
write=1
for a in "$@"; do
  case "$a" in
    --large) models+=(armadillo_13m) ;;
    --no-write) write=0 ;;
    *) echo "tool_results.sh: unknown argument '$a'" >&2; exit 2 ;;
  esac
done
data=datasets/data
out=out/results
mkdir -p "$out"
tool=${HB_TOOL:-sphere,radius-mm=2,points=1000}
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT
export XDG_CACHE_HOME=$cache

model_args() {  # the mesh and its model options
  case "$1" in
    armadillo|fandisk|bull|blade) echo "$data/meshes/$1.off" ;;
    chess_piece|bumpy_sphere) echo "$data/generated/$1.off" ;;
    femur_bone) echo "$data/generated/femur_ct.nii.gz --volume iso=300" ;;
    armadillo_832k|armadillo_13m)
      local levels=2
      [ "$1" = armadillo_13m ] && levels=4
      local m="$out/$1.off"
      [ -f "$m" ] || "$HB" subdivide "$data/meshes/armadillo.off" -o "$m" --levels "$levels" >&2
      echo "$m" ;;
  esac
}

table_only=${HB_TABLE_ONLY:-0}  # 1: the table from the last run's out/results/tool_*.json
for name in "${models[@]}"; do
  [ "$table_only" = 1 ] && continue
  read -r -a args <<<"$(model_args "$name")"
  mesh=${args[0]}
  opts=("${args[@]:1}")
  box="$out/tool_$name.hbox"
  "$HB" bake "$mesh" "${opts[@]}" -o "$box" >/dev/null
  "$HB" bench "$box" "$mesh" "${opts[@]}" --tool "$tool" --json >"$out/tool_$name.json"
  echo "$name: done" >&2
done
rows=$(/usr/bin/python3 - "$out" "${models[@]}" <<'PY'
import json, sys
sys.path.insert(0, "scripts")
from route_words import tool_route_words
out, names = sys.argv[1], sys.argv[2:]
def us(v): return f"{v:.0f}" if v >= 10 else f"{v:.1f}"
for name in names:
    j = json.load(open(f"{out}/tool_{name}.json"))
    label = name.replace('_', ' ').replace('832k', '832K').replace('13m', '13M')
    ratio = j['exact_tool_tick_p99_us'] / j['box_tool_tick_p99_us']
    verdict = f"{ratio:.1f}x faster" if ratio >= 1.05 else (f"{1/ratio:.1f}x slower" if ratio <= 1/1.05 else "as fast")
    print(f"| {label} | {j['triangles']:,} | {tool_route_words(j['route'])} | {j['tool_contact_ticks']:,} | "
          f"{100*j['tool_perceptible_tick_share']:.3g}% | {us(j['box_tool_tick_p50_us'])} / {us(j['box_tool_tick_p99_us'])} us | "
          f"{us(j['exact_tool_tick_p50_us'])} / {us(j['exact_tool_tick_p99_us'])} us ({j['exact_tool_api']}) | {verdict} | "
          f"{us(j['sdf_tool_tick_p99_us'])} us, {100*j['sdf_perceptible_tick_share']:.3g}% felt |")
PY
)
if [ "$table_only" = 1 ]; then
  stamp=$(cat "$out/tool_stamp.txt")
else
  stamp="$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git rev-parse --short HEAD), load $(cut -d' ' -f1-3 /proc/loadavg) at the end"
  echo "$stamp" >"$out/tool_stamp.txt"
fi
{
  echo "Tool \`$tool\` along 20 slides (0.5 mm deep, 30 mm/s, 5,000 ticks) on each model's default bake, one core, one run ($stamp):"
  echo
  echo "| model | triangles | answered by | contact ticks | perceptibly different | box tick p50 / p99 | exact tick p50 / p99 | box at p99 | distance field (same memory) p99 |"
  echo "|---|---|---|---|---|---|---|---|---|"
  echo "$rows"
} >"$out/tools.md"
cat "$out/tools.md"
if [ "$write" = 1 ]; then
  /usr/bin/python3 - "$out/tools.md" <<'PY'
import re, sys
table = open(sys.argv[1]).read()
readme = open("README.md").read()
begin, end = "<!-- tools:begin (scripts/tool_results.sh writes this table; do not edit) -->", "<!-- tools:end -->"
if begin not in readme: sys.exit("README.md has no tools markers")
head, rest = readme.split(begin, 1)
_, tail = rest.split(end, 1)
open("README.md", "w").write(head + begin + "\n" + table + end + tail)
PY
fi
