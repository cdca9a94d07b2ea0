#!/usr/bin/env bash
# Obtains the test datasets into datasets/data/ (git-ignored). Idempotent: returns at once
# when the data is already there.
#   1. CGAL's sample meshes (.off) from Debian's libcgal-demo package: `apt-get download`
#      (apt-get update only if that fails), `dpkg-deb -x`, then data/meshes/*.off from the
#      data.tar.gz inside, into datasets/data/meshes/.
#   2. If the path of the built hb_generate_datasets is given as $1, the generated objects
#      (bumpy_sphere.off, chess_piece.off) into datasets/data/generated/.
# Usage: datasets/fetch.sh [build/datasets/hb_generate_datasets]
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
meshes="$here/data/meshes"
generated="$here/data/generated"
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
fi
