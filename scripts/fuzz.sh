#!/usr/bin/env bash
# Runs the libFuzzer targets of tests/fuzz (built by scripts/build_sanitized.sh into
# build-asan/), each for SECONDS (default 600) or, with --runs N, for N executions, from the
# seeds in tests/fuzz/corpus/<target>/ plus what earlier runs found (build-asan/fuzz-corpus/).
# Inputs that break an invariant, crash, hang (> 10 s) or use more than 1 GB are saved in
# build-asan/fuzz-artifacts/ and make the script fail. Prints executions per target.
# HB_FUZZ_JOBS=N runs N targets at once (default 1; ./test.sh runs 2, one a core).
# HB_FUZZ_SEED=S fixes libFuzzer's random seed (./test.sh uses 1), so a short run from the
# seed corpus repeats the same mutations: CI checks a known prefix, long runs explore.
#   scripts/fuzz.sh [SECONDS | --runs N] [TARGET...]     (targets: off obj ply stl box servo_log segments_csv volume_header dicom gltf cad)
set -euo pipefail
cd "$(dirname "$0")/.."
limit=(-max_total_time=600)
if [ "${1:-}" = "--runs" ]; then limit=(-runs="$2"); shift 2
elif [ -n "${1:-}" ] && [[ "$1" =~ ^[0-9]+$ ]]; then limit=(-max_total_time="$1"); shift; fi
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(off obj ply stl box servo_log segments_csv volume_header dicom gltf cad)
jobs=${HB_FUZZ_JOBS:-1}
seed_opt=()
if [ -n "${HB_FUZZ_SEED:-}" ]; then
  [[ "$HB_FUZZ_SEED" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: HB_FUZZ_SEED must be a positive integer, not '$HB_FUZZ_SEED'" >&2; exit 2; }
  seed_opt=(-seed="$HB_FUZZ_SEED")
fi
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "fuzz.sh: HB_FUZZ_JOBS must be a positive integer, not '$jobs'" >&2; exit 2; }
for t in "${targets[@]}"; do
  case "$t" in off|obj|ply|stl|box|servo_log|segments_csv|volume_header|dicom|gltf|cad) ;;
    *) echo "fuzz.sh: unknown target '$t' (targets: off obj ply stl box servo_log segments_csv volume_header dicom gltf cad)" >&2; exit 2 ;;
  esac
done
[ -x build-asan/tests/fuzz/fuzz_box ] && [ -x build-asan/tests/fuzz/fuzz_cad ] || bash scripts/build_sanitized.sh
mkdir -p build-asan/fuzz-artifacts
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan_suppressions.txt}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

# One target: its log in build-asan/fuzz-<target>.log, its verdict in build-asan/fuzz-<target>.result.
run_one() {
  local t=$1 work=build-asan/fuzz-corpus/$1 log=build-asan/fuzz-$1.log
  mkdir -p "$work"
  # Each process has its own scratch file (fuzz_support.h names it after the pid).
  if build-asan/tests/fuzz/fuzz_$t "${limit[@]}" "${seed_opt[@]}" -rss_limit_mb=1024 -malloc_limit_mb=1024 -timeout=10 \
       -print_final_stats=1 -artifact_prefix=build-asan/fuzz-artifacts/$t- "$work" tests/fuzz/corpus/$t >"$log" 2>&1; then
    echo ok >build-asan/fuzz-$t.result
  else
    echo FAILED >build-asan/fuzz-$t.result
  fi
}

running=0
for t in "${targets[@]}"; do
  rm -f build-asan/fuzz-$t.result
  run_one "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
done
wait || true

status=0
summary=""
for t in "${targets[@]}"; do
  log=build-asan/fuzz-$t.log
  result=$(cat build-asan/fuzz-$t.result 2>/dev/null || echo FAILED)
  if [ "$result" != ok ]; then status=1; echo "fuzz.sh: $t failed; end of $log:" >&2; tail -40 "$log" >&2; fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  peak=$(grep -o 'stat::peak_rss_mb: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  summary+=$(printf '%-14s %-6s %10s executions, peak RSS %5s MB' "$t" "$result" "$runs" "$peak")$'\n'
done
printf 'fuzz: target         result  executions (%s)\n%s' "${limit[*]}" "$summary"
exit $status
