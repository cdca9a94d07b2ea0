#!/usr/bin/env bash
# Runs the libFuzzer targets of tests/fuzz (built by scripts/build_sanitized.sh into
# build-asan/), each for SECONDS (default 600) or, with --runs N, for N executions, from the
# seeds in tests/fuzz/corpus/<target>/ plus what earlier runs found (build-asan/fuzz-corpus/).
# Inputs that break an invariant, crash, hang (> 10 s) or use more than 1 GB are saved in
# build-asan/fuzz-artifacts/ and make the script fail. Prints executions per target.
#   scripts/fuzz.sh [SECONDS | --runs N] [TARGET...]     (targets: off obj ply stl box servo_log segments_csv)
set -euo pipefail
cd "$(dirname "$0")/.."
limit=(-max_total_time=600)
if [ "${1:-}" = "--runs" ]; then limit=(-runs="$2"); shift 2
elif [ -n "${1:-}" ] && [[ "$1" =~ ^[0-9]+$ ]]; then limit=(-max_total_time="$1"); shift; fi
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(off obj ply stl box servo_log segments_csv)
[ -x build-asan/tests/fuzz/fuzz_box ] || bash scripts/build_sanitized.sh
mkdir -p build-asan/fuzz-artifacts
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan_suppressions.txt}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
summary=""
for t in "${targets[@]}"; do
  work=build-asan/fuzz-corpus/$t
  mkdir -p "$work"
  log=build-asan/fuzz-$t.log
  if build-asan/tests/fuzz/fuzz_$t "${limit[@]}" -rss_limit_mb=1024 -malloc_limit_mb=1024 -timeout=10 \
       -print_final_stats=1 -artifact_prefix=build-asan/fuzz-artifacts/$t- "$work" tests/fuzz/corpus/$t >"$log" 2>&1; then
    result=ok
  else
    result=FAILED; status=1
    tail -40 "$log" >&2
  fi
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  peak=$(grep -o 'stat::peak_rss_mb: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
  summary+=$(printf '%-14s %-6s %10s executions, peak RSS %5s MB' "$t" "$result" "$runs" "$peak")$'\n'
done
printf 'fuzz: target         result  executions\n%s' "$summary"
exit $status
