#!/usr/bin/env bash
# The main job: install what is missing, build, fetch the datasets, then run HapticBox.
# With a display and the desktop window built, opens it on the default model; otherwise runs
# the headless main job: bake the default model, evaluate it against the exact answer and
# benchmark it, printing the summary, and write the error report.
set -euo pipefail
cd "$(dirname "$0")"
bash scripts/build.sh
bash datasets/fetch.sh build/datasets/hb_generate_datasets

MODEL=${HB_MODEL:-datasets/data/meshes/armadillo.off}
HB=build/cli/hapticbox
GUI=build/qt_ui/hapticbox-gui
if [ -n "${DISPLAY:-}" ] && [ -x "$GUI" ]; then
  exec "$GUI" "$MODEL"
fi
[ -x "$GUI" ] && echo "run.sh: no display: running the headless main job instead of the desktop window"

mkdir -p out
echo "== mesh"
"$HB" info "$MODEL"
echo "== bake: the default, budgeted bake (hb::default_recipe): the paper's raw haptic box first, kept only where no"
echo "   hand could tell it from exact (at most 0.1% of probes and of slide ticks perceptibly different, forces with the"
echo "   model fitted to an 80 mm workspace, 1500 N/m); otherwise exact answers by the faster of Embree and the surface cells"
"$HB" bake "$MODEL" -o out/default.hbox
"$HB" info out/default.hbox | grep -E '^(boxes|bytes|codec|compression_ratio|table_bytes|refine|triangle_id_bytes|surface_bytes|scene_grid_bytes|budget):'
echo "== eval against the exact Embree answer"
"$HB" eval out/default.hbox "$MODEL" --samples 20000 --seed 1 | tee out/eval.txt
echo "== bench (one core)"
"$HB" bench out/default.hbox "$MODEL" | tee out/bench.txt
echo "== report (report.html, summary.json, samples.csv)"
"$HB" report out/default.hbox "$MODEL" -o out/report --sweep none --stability
echo "== summary (the haptic box against the exact answer, same probes; from out/report/summary.txt and bench)"
cat out/report/summary.txt
grep -E '^verdict:' out/bench.txt | sed 's/^verdict: /bench: /' || true
grep -E 'p99: ' out/bench.txt | sed 's/^ */bench, single-query tail: /' || true
# The other side: the paper's own test object, where its raw box holds (unless HB_MODEL names
# another model, whose job this is not).
if [ -z "${HB_MODEL:-}" ]; then
  BUMPY=datasets/data/generated/bumpy_sphere.off
  echo "== where the paper's method holds: its bumpy sphere (327K triangles), the same default bake"
  "$HB" bake "$BUMPY" -o out/bumpy_sphere.hbox | grep -E '^(baked|budget)' || true
  "$HB" eval out/bumpy_sphere.hbox "$BUMPY" --samples 20000 --seed 1 | grep -E 'perceptibly different' | head -1 || true
  "$HB" bench out/bumpy_sphere.hbox "$BUMPY" | grep -E '^verdict:' | sed 's/^verdict: /bench: /' || true
fi
echo "run.sh: the report is in out/report/report.html"
