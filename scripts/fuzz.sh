#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, the `fuzz` preset: clang, ASan + UBSan) and runs each for a bounded time
# from seeds derived from the shared scenes. Fails on any crash, hang, leak, sanitizer report or broken error
# message; prints executions per target and writes a JSON summary. docs/reliability.md explains the targets.
#
#   scripts/fuzz.sh [TARGET...]        targets: ply ply_header obj gltf glb scene_json scene_refs image (default: all)
#
# Environment:
#   PRISM_FUZZ_SECONDS   seconds per target (default 60)
#   PRISM_FUZZ_JOBS      targets fuzzed at once (default: the number of cores)
#   PRISM_SCENES         the shared scenes the seeds come from (default ../shared/scenes beside the repository)
#   PRISM_FUZZ_OUT       logs, crash inputs and fuzz-summary.json (default build/fuzz/results)
#   PRISM_FUZZ_CORPUS    keep the grown corpora here across runs (default: a temporary folder, removed)
#   PRISM_FUZZ_BIN       run the fuzzers already built in this folder instead of building the fuzz preset
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
seconds=${PRISM_FUZZ_SECONDS:-60}
jobs=${PRISM_FUZZ_JOBS:-$(nproc)}
scenes=${PRISM_SCENES:-$repo/../shared/scenes}
out=${PRISM_FUZZ_OUT:-$repo/build/fuzz/results}
all_targets=(ply ply_header obj gltf glb scene_json scene_refs image)
targets=("${@:-${all_targets[@]}}")
started=$(date +%s)

declare -A dictionary=([ply]=ply [ply_header]=ply [obj]=obj [gltf]=gltf [glb]=gltf [scene_json]=scene_json
                       [scene_refs]=scene_refs [image]=image)
for target in "${targets[@]}"; do
  [ -n "${dictionary[$target]:-}" ] || { echo "fuzz.sh: unknown target '$target' (${all_targets[*]})" >&2; exit 2; }
done
[ -d "$scenes" ] || { echo "fuzz.sh: $scenes: no such folder (the shared scenes the seeds come from)" >&2; exit 1; }

if [ -n "${PRISM_FUZZ_BIN:-}" ]; then
  bin=$PRISM_FUZZ_BIN   # fuzzers built elsewhere (another machine with more cores runs them)
else
  echo "== build (fuzz preset: clang, libFuzzer, ASan + UBSan)"
  cmake --preset fuzz >/dev/null
  cmake --build --preset fuzz -j "$(nproc)" --target prism_fuzzers
  bin=$repo/build/fuzz/fuzz
fi
built=$(date +%s)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The targets write every input to a file (the loaders take paths): on tmpfs that costs no disk I/O.
scratch_tmp=$work
if [ -d /dev/shm ] && [ -w /dev/shm ]; then scratch_tmp=/dev/shm; fi
corpora=${PRISM_FUZZ_CORPUS:-$work/corpus}
rm -rf "$out/logs" "$out/crashes" "$out/fuzz-summary.json"
mkdir -p "$out/logs" "$out/crashes"
# Seeds are derived from the shared scenes at run time (fuzz/fuzz_seeds.cpp); nothing of them is committed.
"$bin/fuzz_seeds" "$scenes" "$repo" "$work/seeds"

# One target: the grown corpus first (libFuzzer writes new inputs there), the seeds read-only second.
# -timeout: an input taking longer than 10 s is a hang; -rss_limit_mb / -malloc_limit_mb: a small file must not
# make a loader allocate 1 GiB or grow the process past it (both are findings, like a crash).
run_target() {
  local target=$1
  local status=0 begin
  begin=$(date +%s)
  mkdir -p "$corpora/$target" "$work/seeds/$target"
  TMPDIR=$scratch_tmp ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:symbolize=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$bin/fuzz_$target" "$corpora/$target" "$work/seeds/$target" \
      -dict="$repo/fuzz/dict/${dictionary[$target]}.dict" -max_total_time="$seconds" -timeout=10 \
      -rss_limit_mb=1024 -malloc_limit_mb=1024 -print_final_stats=1 \
      -artifact_prefix="$out/crashes/$target-" >"$out/logs/$target.log" 2>&1 || status=$?
  echo "$status $(($(date +%s) - begin))" >"$out/logs/$target.status"
}

echo "== fuzzing ${targets[*]}: ${seconds} s each, $jobs at a time (logs in $out/logs)"
running=0
for target in "${targets[@]}"; do
  run_target "$target" &
  running=$((running + 1))
  if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
done
wait || true

# libFuzzer's final stats: "stat::number_of_executed_units: N", "stat::peak_rss_mb: N"; corpus size from the
# last status line ("corp: N/SIZE").
final_stat() { sed -n "s/^stat::$1: *\([0-9]*\).*/\1/p" "$2" | tail -1; }
failed=()
rows=()
printf '%-11s %9s %12s %9s %8s %9s  %s\n' target seconds executions exec/s corpus rss_mb result
for target in "${targets[@]}"; do
  log=$out/logs/$target.log
  read -r status took <"$out/logs/$target.status" || { status=1; took=0; }
  executions=$(final_stat number_of_executed_units "$log"); executions=${executions:-0}
  rate=$(final_stat average_exec_per_sec "$log"); rate=${rate:-0}
  rss=$(final_stat peak_rss_mb "$log"); rss=${rss:-0}
  corpus=$(grep -o 'corp: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*' || true); corpus=${corpus:-0}
  result=ok
  crash=$(ls "$out/crashes/$target-"* 2>/dev/null | head -1 || true)
  if [ "$status" != 0 ] || [ -n "$crash" ]; then
    result=failed
    failed+=("$target")
  fi
  printf '%-11s %9s %12s %9s %8s %9s  %s\n' "$target" "$took" "$executions" "$rate" "$corpus" "$rss" \
    "$result${crash:+ ($crash)}"
  rows+=("$(printf '    {"target": "%s", "seconds": %s, "executions": %s, "executions_per_second": %s, "corpus_inputs": %s, "peak_rss_mb": %s, "result": "%s", "crash_input": "%s"}' \
    "$target" "$took" "$executions" "$rate" "$corpus" "$rss" "$result" "${crash#"$repo/"}")")
done
finished=$(date +%s)

{
  echo "{"
  echo "  \"commit\": \"${PRISM_COMMIT:-$(git rev-parse --short=12 HEAD 2>/dev/null || echo unknown)}\","
  echo "  \"date\": \"$(date -u +%Y-%m-%dT%H:%M:%SZ)\","
  echo "  \"host\": {\"cpu\": \"$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)\", \"threads\": $(nproc)},"
  echo "  \"compiler\": \"${PRISM_FUZZ_COMPILER:-$(clang++ --version 2>/dev/null | head -1)}\","
  echo "  \"seconds_per_target\": $seconds, \"parallel_targets\": $jobs,"
  echo "  \"build_seconds\": $((built - started)), \"total_seconds\": $((finished - started)),"
  echo "  \"targets\": ["
  for i in "${!rows[@]}"; do
    [ "$i" -lt $((${#rows[@]} - 1)) ] && echo "${rows[$i]}," || echo "${rows[$i]}"
  done
  echo "  ]"
  echo "}"
} >"$out/fuzz-summary.json"
echo "summary: $out/fuzz-summary.json (build $((built - started)) s, total $((finished - started)) s)"

if [ ${#failed[@]} -gt 0 ]; then
  for target in "${failed[@]}"; do
    echo "== fuzz_$target failed; the end of its log:"
    grep -v '^#[0-9]' "$out/logs/$target.log" | tail -40
  done
  echo "fuzz.sh: ${failed[*]} failed; reproduce with build/fuzz/fuzz/fuzz_<target> <crash input>" >&2
  exit 1
fi
