#!/usr/bin/env bash
# Every model format end to end on the real and generated files: info, bake, eval (box against
# exact Embree on the same surface), one line per file. Needs the build and the datasets
# (./test.sh or datasets/fetch.sh build/datasets/hb_generate_datasets).
# Usage: scripts/model_formats_e2e.sh [OUT_DIR] (default out/model_formats); HB_DATA_DIR as fetch.sh.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
hb="$root/build/cli/hapticbox"
data="${HB_DATA_DIR:-$root/datasets/data}"
out="${1:-$root/out/model_formats}"
mkdir -p "$out"
v="$data/volumes"
g="$data/generated"
run() {  # name file [model options...] (BAKE_ARGS: extra bake options)
  local name="$1" file="$2"
  shift 2
  local bake_args=(${BAKE_ARGS:-})
  local t0 t1
  t0=$(date +%s.%N)
  "$hb" info "$file" "$@" --json > "$out/$name.info.json" 2> "$out/$name.log"
  "$hb" bake "$file" "$@" "${bake_args[@]}" -o "$out/$name.hbox" -m 16 -n 8 --json > "$out/$name.bake.json" 2>> "$out/$name.log"
  "$hb" eval "$out/$name.hbox" "$file" "$@" --samples 5000 --json > "$out/$name.eval.json" 2>> "$out/$name.log"
  t1=$(date +%s.%N)
  python3 - "$out/$name" "$name" "$t0" "$t1" <<'PY'
import json, sys
base, name, t0, t1 = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
i = json.load(open(base + ".info.json")); e = json.load(open(base + ".eval.json")); b = json.load(open(base + ".bake.json"))
extra = ""
if "dimensions" in i: extra = "dims %s spacing %s iso/label %s" % (i["dimensions"], [round(s, 3) for s in i["spacing_mm"]], i.get("iso", i.get("label")))
if "faces" in i: extra = "solids %d faces %d chordal %.3g measured %.3g mm" % (i["solids"], i["faces"], i["chordal_deviation_mm"], i["measured_deviation_mm"])
if "file_unit_read_from" in i: extra = "unit %s (%s)" % (i["unit"], i["file_unit_read_from"])
print("%-22s %-13s %8d tri  diag %7.1f mm  boxes %2d  agreement %.4f  force err median %.4f p95 %.4f  %5.1f s  %s" % (
    name, i["format"], i["triangles"], i["diagonal"], b.get("boxes", 1), e["contact_agreement"], e["force_error_median"],
    e["force_error_p95"], t1 - t0, extra))
PY
}
run mri_anatomical "$v/anatomical.nii"
run ct_dicom_CT5N "$v/dicom/CT5N" --volume iso=-500
run phantom_nii "$g/ct_phantom.nii.gz" --volume iso=-480
run phantom_mha_bone "$g/ct_phantom.mha" --volume iso=370
run phantom_nrrd_smooth "$g/ct_phantom.nrrd" --volume iso=-480,smooth=15,triangles=20000
run phantom_labels "$g/ct_phantom_labels.nii.gz" --volume label=2
run step_solid "$g/reference_solid.step"
BAKE_ARGS="--pieces faces" run step_solid_faces "$g/reference_solid.step"
for f in gltf glb 3mf dae fbx; do run "elephant_$f" "$g/elephant.$f"; done
