#!/usr/bin/env bash
# Installs missing Debian packages, configures and builds HapticBox (Release) into build/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
# Unity build (CMake compiles a target's sources 8 at a time in one translation unit): the
# headers (CLI11, VTK, Qt, GoogleTest, Eigen) are parsed once a batch, which halves the CPU time
# of a clean build. A target's files must therefore not define the same name in an anonymous
# namespace; scripts/check_unity.py checks every target at once. HB_UNITY=0 builds file by file.
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DCMAKE_UNITY_BUILD="$([ "${HB_UNITY:-1}" = 0 ] && echo OFF || echo ON)" >build-configure.log 2>&1 || { cat build-configure.log; exit 1; }
cmake --build build -j"$jobs"
