#!/usr/bin/env bash
# The results table: the default bake of a few real models, measured against the exact answer
# (Embree on the same mesh, the same probes, the same run), stamped with the commit, the date
# and the machine. Rerunning it refreshes the table between the results markers in README.md and
# the whole of docs/results.md. Not run by ./test.sh (it measures; tests assert).
#
#   scripts/results.sh [--quick] [--large] [--huge] [--no-write]
#
#   (default)   elephant, fandisk, armadillo, bunny, chess piece, the armadillo subdivided to
#               832K triangles, the bumpy sphere and the smooth ellipsoid (the smooth, quasi-convex
#               objects the paper's raw box is tried on): about five minutes on 2 cores
#   --quick     elephant and armadillo only
#   --large     also the armadillo subdivided to 13M triangles (a 539 MB OFF; about 5 minutes
#               more, 3.5 GB of memory)
#   --huge      also the armadillo subdivided to 53M triangles (a 1 GB binary PLY; about 8 minutes
#               more, 8 GB of memory)
#   --no-write  print the tables, change no file
#   HB_TABLE_ONLY=1  measure nothing: the tables again from the last run's out/results/ (its
#               stamp and models in out/results/stamp.txt), e.g. after a change of their words
#
# Every model is baked with `hapticbox bake MESH -o BOX` and no other option (the default bake),
# in a cache of its own (so the bake time is a real bake's), then `info --json`,
# `eval --seed 2 --json` (20,000 probes) and `bench --seed 2 --json` (one core, box and exact on
# the same probes). The JSON of every step stays in out/results/. Needs the build
# (bash scripts/build.sh) and the datasets (bash datasets/fetch.sh build/datasets/hb_generate_datasets).
set -euo pipefail
cd "$(dirname "$0")/.."
HB=${HB:-build/cli/hapticbox}
models=(elephant fandisk armadillo bunny chess_piece armadillo_832k bumpy_sphere smooth_ellipsoid)
write=1
for arg in "$@"; do
  case "$arg" in
    --quick) models=(elephant armadillo) ;;
    --large) models+=(armadillo_13m) ;;
    --huge) models+=(armadillo_53m) ;;
    --no-write) write=0 ;;
    -h|--help) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "results.sh: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
  esac
done
table_only=${HB_TABLE_ONLY:-0}
out=out/results
if [ "$table_only" = 1 ]; then
  [ -f "$out/stamp.txt" ] || { echo "results.sh: HB_TABLE_ONLY=1 needs a previous run's $out/stamp.txt" >&2; exit 1; }
  { read -r commit; read -r started; read -r machine; read -r load; read -r version; read -r took
    read -r -a models; } < "$out/stamp.txt"
else
[ -x "$HB" ] || { echo "results.sh: $HB is not built (bash scripts/build.sh)" >&2; exit 1; }
data=datasets/data
[ -f "$data/meshes/armadillo.off" ] ||
  { echo "results.sh: no datasets in $data (bash datasets/fetch.sh build/datasets/hb_generate_datasets)" >&2; exit 1; }

mkdir -p "$out"
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT
export XDG_CACHE_HOME=$cache  # the box cache of this run only: every bake is baked

mesh_of() {
  case "$1" in
    elephant|fandisk|armadillo) echo "$data/meshes/$1.off" ;;
    bunny) echo "$data/meshes/bunny00.off" ;;
    chess_piece|bumpy_sphere|smooth_ellipsoid) echo "$data/generated/$1.off" ;;
    armadillo_832k|armadillo_13m|armadillo_53m)
      local levels=2 ext=off
      [ "$1" = armadillo_13m ] && levels=4
      [ "$1" = armadillo_53m ] && levels=5 ext=ply  # binary: a 2 GB OFF reads slowly
      local m="$out/$1.$ext"
      if [ ! -f "$m" ] || [ "$data/meshes/armadillo.off" -nt "$m" ]; then
        "$HB" subdivide "$data/meshes/armadillo.off" -o "$m" --levels "$levels" >&2
      fi
      echo "$m" ;;
  esac
}

# The stamp: what was measured, when, where.
commit=${HB_COMMIT:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)}
if [ -z "${HB_COMMIT:-}" ] && ! git diff --quiet HEAD -- src cli device vtk_pipelines report mpi 2>/dev/null; then
  commit="$commit+changes"
fi
cpu=$(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //')
machine="$cpu, $(nproc) cores, $(free -g | awk '/^Mem:/ { print $2 }') GB, $(uname -sr)"
started=$(date -u '+%Y-%m-%d %H:%M UTC')
load=$(cut -d' ' -f1-3 /proc/loadavg)
version=$("$HB" --version | head -n 1 | sed 's/ (heap.*//')

start=$SECONDS
for name in "${models[@]}"; do
  mesh=$(mesh_of "$name")
  [ -f "$mesh" ] || { echo "results.sh: $mesh is missing (datasets/fetch.sh with the generator)" >&2; exit 1; }
  echo "results.sh: $name ($mesh)" >&2
  "$HB" bake "$mesh" -o "$out/$name.hbox" --json > "$out/$name.bake.json" 2> "$out/$name.bake.log"
  "$HB" info "$out/$name.hbox" --json > "$out/$name.info.json"
  "$HB" eval "$out/$name.hbox" "$mesh" --seed 2 --json > "$out/$name.eval.json"
  "$HB" bench "$out/$name.hbox" "$mesh" --seed 2 --json > "$out/$name.bench.json"
done
took=$((SECONDS - start))
printf '%s\n' "$commit" "$started" "$machine" "$load" "$version" "$took" "${models[*]}" > "$out/stamp.txt"
fi

python3 - "$out" "$write" "$commit" "$started" "$machine" "$load" "$version" "$took" "${models[@]}" <<'PY'
import json, os, re, sys
sys.path.insert(0, "scripts")
from route_words import answer_words

out, write, commit, started, machine, load, version, took = sys.argv[1:9]
models = sys.argv[9:]
titles = {"elephant": "elephant", "fandisk": "fandisk", "armadillo": "armadillo", "bunny": "bunny",
          "chess_piece": "chess piece", "armadillo_832k": "armadillo 832K", "armadillo_13m": "armadillo 13M",
          "armadillo_53m": "armadillo 53M",
          "bumpy_sphere": "bumpy sphere", "smooth_ellipsoid": "smooth ellipsoid"}

def read(name, step):
    with open(os.path.join(out, f"{name}.{step}.json")) as f:
        return json.load(f)

def pct(x):
    return f"{100 * x:.3g}%"

def ratio(box, exact):  # "1.6x slower" / "2.1x faster" / "as fast" (within 5%)
    r = box / exact
    if 1 / 1.05 < r < 1.05:
        return "as fast"
    r, word = (r, "slower") if r > 1 else (1 / r, "faster")
    return f"{r:.1f}x {word}" if r < 10 else f"{r:.0f}x {word}"

rows, perceptible = [], True
for m in models:
    bake, info, ev, be = read(m, "bake"), read(m, "info"), read(m, "eval"), read(m, "bench")
    p = ev.get("perceptible")
    perceptible &= isinstance(p, dict) and "share" in p
    rows.append(dict(
        model=titles.get(m, m), triangles=f"{info['source_triangles']:,}",
        boxes=str(info["boxes"]), file=f"{info['bytes'] / 1e6:.3g} MB",
        bake=f"{bake.get('budget', {}).get('seconds', bake['seconds']):.3g} s",  # the whole bake
        agreement=f"{pct(ev['contact_agreement'])} ({ev['false_contacts']} / {ev['missed_contacts']})",
        force=f"{ev['force_error_median'] * 100:.2g}% / {ev['force_error_p95'] * 100:.2g}%",
        direction=f"{ev['angle_error_p99_deg']:.2g} deg",
        perceptible=(f"{pct(p['share'])} ({p.get('probes', '?')})" if isinstance(p, dict) and "share" in p else ""),
        light=(f"{pct(ev['light_touch']['perceptible_share'])} ({ev['light_touch']['perceptible']})"
               if isinstance(ev.get("light_touch"), dict) else ""),
        random=f"{be['box_ns']:,.0f} / {be['exact_ns']:,.0f} ns, {ratio(be['box_ns'], be['exact_ns'])}",
        batched=ratio(be["box_batched_ns"], be["exact_batched_ns"]),
        coherent=ratio(be["box_coherent_ns"], be["exact_coherent_ns"]),
        strokes=f"{be['box_stroke_ns']:,.0f} / {be['exact_stroke_ns']:,.0f} ns, {ratio(be['box_stroke_ns'], be['exact_stroke_ns'])}",
        tail=f"{be['box_single_tail']['probe_p999_ns'] / 1000:.2g} / {be['exact_single_tail']['probe_p999_ns'] / 1000:.2g} us",
        met="met" if info.get("budget_report", {}).get("met") else "MISSED",
        answer=answer_words(info.get("budget_report") or {})))

def table(cols):
    head = "| " + " | ".join(t for _, t in cols) + " |\n|" + "---|" * len(cols) + "\n"
    return head + "".join("| " + " | ".join(r[k] for k, _ in cols) + " |\n" for r in rows)

short = [("model", "model"), ("triangles", "triangles"), ("file", "file"), ("bake", "bake"),
         ("answer", "answered by"), ("force", "force error median / p95")]
if perceptible:
    short.append(("perceptible", "perceptible (probes)"))
short += [("random", "random query, box / exact"), ("strokes", "strokes, box / exact")]
full = [("model", "model"), ("triangles", "triangles"), ("boxes", "boxes"), ("file", "file"),
        ("bake", "bake"), ("met", "budget"), ("answer", "answered by"), ("agreement", "contact agreement (false / missed)"),
        ("force", "force error median / p95"), ("direction", "direction p99")]
if perceptible:
    full.append(("perceptible", "perceptible (probes)"))
if all(r["light"] for r in rows):
    full.append(("light", "perceptible (light touch, any angle)"))
full += [("random", "random"), ("batched", "batched"), ("coherent", "coherent"), ("strokes", "strokes"),
         ("tail", "per-probe p99.9, box / exact")]

stamp = (f"Made by `scripts/results.sh` on {started}, commit {commit} ({version}), {machine}, "
         f"load average {load} at the start; {took} s.")
readme_block = (
    "<!-- results:begin (scripts/results.sh writes this table; do not edit) -->\n"
    + table(short) + "\n"
    "Default bake (`hapticbox bake MESH -o BOX`), then `eval --seed 2` (20,000 probes) and `bench --seed 2`\n"
    f"(one core), box against exact Embree on the same probes in the same run, at commit {commit}. The\n"
    "machine, the date, every order, the tails and the budget: `docs/results.md`.\n"
    "<!-- results:end -->")
doc = f"""# Results

Rerun `scripts/results.sh` to refresh this page and the README's table (do not
edit by hand). {stamp}

Each model is baked with the default bake (`hapticbox bake MESH -o BOX`, no other option: the
perceptual budget: at most 0.1% of probes and of slide ticks a hand would feel as different, the
raw box tried first, exact by the faster of Embree and the surface cells otherwise), in a box cache of its own
so the bake time is a real bake's (2 cores). Accuracy: `hapticbox eval BOX MESH --seed 2`, 20,000
probes, against exact Embree on the same mesh; contact agreement with its false and missed
contacts, the relative force error over the probes both answers touch, the direction error's 99th
percentile{", and the share of probes whose difference a hand would feel (`perception.md`)" if perceptible else ""}; and as
many light touches at any angle (within 85 degrees of the normal, tips up to 0.5% of the
diagonal deep, under 0.6 N), the share a hand would feel. Speed: `hapticbox bench BOX MESH
--seed 2`, one core, box and exact on the same probes in the same run, in four orders (`speed.md`):
random (one query at a time), batched, coherent (sorted along a space-filling curve) and strokes
(hand-like circles, probes 1 ms apart); the tail is each probe's median over 5 rounds, its 99.9th
percentile. The budget column is the bake's own check on 20,000 fresh probes (seed 102). On a
shared machine absolute times move with the load; the ratios within one run are what count.

{table(full)}
The JSON of every step is in `out/results/` after a run (`MODEL.bake.json`, `.info.json`,
`.eval.json`, `.bench.json`).
"""
print(table(full))
print(stamp)
if write == "1":
    with open("docs/results.md", "w") as f:
        f.write(doc)
    with open("README.md") as f:
        readme = f.read()
    pattern = re.compile(r"<!-- results:begin.*?<!-- results:end -->", re.S)
    if not pattern.search(readme):
        sys.exit("results.sh: README.md has no <!-- results:begin --> ... <!-- results:end --> markers")
    with open("README.md", "w") as f:
        f.write(pattern.sub(lambda _: readme_block, readme))
    print("results.sh: wrote docs/results.md and the table in README.md")
PY
