#!/usr/bin/env bash
# Builds build-asan/: the core and device test suites and the libFuzzer targets, with clang,
# AddressSanitizer + UndefinedBehaviorSanitizer (+ float-cast-overflow) and libFuzzer's
# coverage instrumentation (one build serves both: every object instrumented once). Only
# what those need is built (no VTK, Qt, CLI or benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
# -gline-tables-only: file and line in the sanitizers' stack traces at less compile time than -g.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 -gline-tables-only -DNDEBUG" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ "${launcher[@]}" \
  -DCMAKE_UNITY_BUILD="$([ "${HB_UNITY:-1}" = 0 ] && echo OFF || echo ON)" -DHB_SANITIZE=ON -DHB_FUZZ=ON -DHB_BUILD_VTK=OFF -DHB_BUILD_GUI=OFF -DHB_BUILD_BENCH=OFF \
  >build-asan-configure.log 2>&1 || { cat build-asan-configure.log; exit 1; }
cmake --build build-asan -j"$jobs" --target hb_core_tests hb_device_tests hb_fuzz_targets
