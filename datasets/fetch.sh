#!/usr/bin/env bash
# Obtains the test datasets into datasets/data/ (git-ignored). Idempotent: returns at once
# when the data is already there.
#   1. CGAL's sample meshes (.off) from Debian's libcgal-demo package: `apt-get download`
#      (apt-get update only if that fails), `dpkg-deb -x`, then data/meshes/*.off from the
#      data.tar.gz inside, into datasets/data/meshes/.
#   2. Real medical volumes the same way: Debian's python3-nibabel (an MRI,
#      tests/data/anatomical.nii, plus standard.nii.gz) and python3-pydicom (CT and MR DICOM:
#      data/test_files/CT_small.dcm, MR_small.dcm and the series of dicomdirtests/) into
#      datasets/data/volumes/ (dicom/CT5N is a 5-slice CT series; dicom/CT2 has missing slices
#      and dicom/MR2 mixed orientations, kept as real bad input).
#   3. If the path of the built hb_generate_datasets is given as $1, the generated objects
#      (bumpy_sphere.off, chess_piece.off) into datasets/data/generated/; and when
#      hb_generate_models sits next to it, the CT phantom (.nii.gz .mha .nrrd, label map), the
#      OpenCASCADE reference solid (.step), glTF/3MF/Collada/FBX exports of a CGAL mesh, and
#      femur_ct.nii.gz and the DICOM series femur_ct_dicom/: a CT synthesized from CGAL's
#      femur.off (nothing downloaded; see datasets/generate_models.cpp) with femur_ct_source.off,
#      the surface it was made from.
# HB_DATA_DIR overrides datasets/data (for trying the script without touching the shared copy).
# Usage: datasets/fetch.sh [build/datasets/hb_generate_datasets]
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
data="${HB_DATA_DIR:-$here/data}"
meshes="$data/meshes"
generated="$data/generated"
volumes="$data/volumes"
generator="${1:-}"

if [[ -f "$meshes/armadillo.off" ]]; then
  echo "fetch.sh: CGAL meshes already in $meshes ($(find "$meshes" -name '*.off' | wc -l) files)"
else
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  # As root, apt warns that the download is "unsandboxed" (its _apt user cannot write to a
  # private temp dir): harmless.
  echo "fetch.sh: downloading libcgal-demo with apt-get into $tmp"
  if ! (cd "$tmp" && apt-get download -q libcgal-demo); then
    echo "fetch.sh: download failed, running apt-get update and retrying"
    apt-get update -q
    (cd "$tmp" && apt-get download -q libcgal-demo)
  fi
  deb="$(find "$tmp" -maxdepth 1 -name 'libcgal-demo_*.deb' | head -n 1)"
  dpkg-deb -x "$deb" "$tmp/root"
  data_tar="$(find "$tmp/root" -name 'data.tar.gz' | head -n 1)"
  if [[ -z "$data_tar" ]]; then
    echo "fetch.sh: no data.tar.gz inside $(basename "$deb")" >&2
    exit 1
  fi
  echo "fetch.sh: extracting data/meshes/*.off from ${data_tar#"$tmp/root"}"
  tar -xzf "$data_tar" -C "$tmp" --wildcards 'data/meshes/*.off'
  mkdir -p "$meshes"
  cp "$tmp"/data/meshes/*.off "$meshes/"
  echo "fetch.sh: $(find "$meshes" -name '*.off' | wc -l) meshes in $meshes"
fi

# Downloads a Debian package into $1 (apt-get update once if the download fails) and unpacks it
# into $1/root.
download_deb() {
  local dir="$1" pkg="$2"
  if ! (cd "$dir" && apt-get download -q "$pkg"); then
    echo "fetch.sh: download of $pkg failed, running apt-get update and retrying"
    apt-get update -q
    (cd "$dir" && apt-get download -q "$pkg")
  fi
  dpkg-deb -x "$(find "$dir" -maxdepth 1 -name "${pkg}_*.deb" | head -n 1)" "$dir/root"
}

if [[ -f "$volumes/anatomical.nii" && -d "$volumes/dicom/CT5N" ]]; then
  echo "fetch.sh: volumes already in $volumes"
else
  vtmp="$(mktemp -d)"
  echo "fetch.sh: downloading python3-nibabel and python3-pydicom with apt-get into $vtmp"
  download_deb "$vtmp" python3-nibabel
  download_deb "$vtmp" python3-pydicom
  nib="$(find "$vtmp/root" -type d -path '*nibabel/tests/data' | head -n 1)"
  dcm="$(find "$vtmp/root" -type d -path '*pydicom/data/test_files' | head -n 1)"
  if [[ -z "$nib" || -z "$dcm" ]]; then
    echo "fetch.sh: no nibabel/tests/data or pydicom/data/test_files in the packages" >&2
    rm -rf "$vtmp"
    exit 1
  fi
  mkdir -p "$volumes/dicom"
  cp "$nib/anatomical.nii" "$nib/standard.nii.gz" "$volumes/"
  cp "$dcm/CT_small.dcm" "$dcm/MR_small.dcm" "$volumes/dicom/"
  for series in 98892001/CT5N 77654033/CT2 98892003/MR2; do
    rm -rf "$volumes/dicom/$(basename "$series")"
    cp -r "$dcm/dicomdirtests/$series" "$volumes/dicom/"
  done
  rm -rf "$vtmp"
  echo "fetch.sh: $(find "$volumes" -type f | wc -l) volume files in $volumes"
fi

if [[ -n "$generator" ]]; then
  if [[ ! -x "$generator" ]]; then
    echo "fetch.sh: $generator is not an executable (build hb_generate_datasets first)" >&2
    exit 1
  fi
  if [[ -f "$generated/bumpy_sphere.off" && -f "$generated/chess_piece.off" &&
        "$generated/chess_piece.off" -nt "$generator" ]]; then
    echo "fetch.sh: generated objects already in $generated"
  else
    "$generator" "$generated"
  fi
  models="$(dirname "$generator")/hb_generate_models"
  if [[ -x "$models" ]]; then
    if [[ -f "$generated/ct_phantom.nii.gz" && -f "$generated/reference_solid.step" &&
          -f "$generated/femur_ct.nii.gz" && -d "$generated/femur_ct_dicom" &&
          "$generated/ct_phantom.nii.gz" -nt "$models" ]]; then
      echo "fetch.sh: generated models already in $generated"
    else
      "$models" "$generated" "$meshes"
    fi
  fi
fi
