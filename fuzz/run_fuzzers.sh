#!/usr/bin/env bash
# Fuzzes each of sweepd's untrusted inputs with libFuzzer (fuzz/fuzz_inputs.h) for a given time.
# Usage: fuzz/run_fuzzers.sh [seconds per target, default 60] [target ...]
#   Builds the `fuzz` preset (clang, ASan + UBSan) into build/fuzz, seeds each corpus from
#   sweepd's own writers (make_seeds) the first time a target runs, keeps the corpora in
#   build/fuzz/corpus so time adds up over runs, and appends each run to build/fuzz/fuzzed_seconds.tsv (target, wall
#   seconds, executions, corpus size, crashes, CPU seconds). CPU seconds are what counts: a run
#   under `nice` on a busy machine gets less CPU than its wall time. A crash leaves its input in
#   build/fuzz/crashes/<target>/; fix it and copy the input to fuzz/regressions/<target>/,
#   which every test run replays (tests/fuzz/fuzz_inputs_test.cpp). Exit 1 when a target crashed.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(frames websocket gltf fbx bvh sweepbind json vmc http)
build=build/fuzz
cmake --preset fuzz >/dev/null
cmake --build "$build" -j "$(nproc)" --target make_seeds "${targets[@]/%/_fuzzer}" >/dev/null
# Seeds for every corpus not there yet (a target added since the corpora were made gets its own;
# make_seeds rewrites the other targets' seed files with the same bytes).
for target in "${targets[@]}"; do
  [ -d "$build/corpus/$target" ] || { "$build/fuzz/make_seeds" "$build/corpus" >/dev/null; break; }
done
failed=0
for target in "${targets[@]}"; do
  corpus="$build/corpus/$target" crashes="$build/crashes/$target"
  mkdir -p "$corpus" "$crashes"
  log="$build/$target.log"
  # ASan's leak check stays on (third-party leaks suppressed by .ci/lsan.supp, each with its
  # reason); -rss_limit_mb keeps a runaway allocation a finding, not a hang.
  TIMEFORMAT='%U %S'
  if { time LSAN_OPTIONS="suppressions=$PWD/.ci/lsan.supp:print_suppressions=0" \
      "$build/fuzz/${target}_fuzzer" "$corpus" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=2048 -max_len=1048576 -artifact_prefix="$crashes/" -print_final_stats=1 \
      >"$log" 2>&1; } 2>"$build/$target.cpu"; then status=ok; else status=CRASH; failed=1; fi
  cpu=$(awk '{printf "%.0f", $1 + $2}' "$build/$target.cpu")
  # The fuzzer's own final stats are the last (a forked child that died may print its own).
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo 0)
  size=$(find "$corpus" -type f | wc -l)
  found=$(find "$crashes" -type f | wc -l)
  printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$target" "$seconds" "$runs" "$size" "$found" "$cpu" \
    >>"$build/fuzzed_seconds.tsv"
  printf '%-10s %s  %ss (CPU %ss)  %s executions  corpus %s  crash inputs %s\n' "$target" "$status" \
    "$seconds" "$cpu" "$runs" "$size" "$found"
  [ "$status" = ok ] || tail -30 "$log"
done
# Runs before CPU seconds were kept (5 columns) count their wall seconds.
awk -F'\t' '{w[$1]+=$2; c[$1]+=(NF>=6?$6:$2); n[$1]+=$3}
  END {for (t in w) printf "fuzzed so far: %-10s %.2f CPU h (%.2f h wall), %d executions\n", t, c[t]/3600, w[t]/3600, n[t]}' \
  "$build/fuzzed_seconds.tsv"
exit $failed
