#!/usr/bin/env bash
# Soak test of the viewer: `prism view` on lavapipe under Xvfb for 10 minutes (the moving object on, so every frame
# also refits and re-uploads the top level), sampling the process's resident memory (VmRSS) every few seconds.
# Pass: after the warm-up, resident memory never grows more than 5% above its first post-warm-up sample (a leak of
# a frame's worth of anything shows within minutes). Writes JSON with every sample.
#
#   bench/soak_viewer.sh [OUT.json]      default bench/results/cpu2/viewer-soak-lavapipe.json
#
# Environment: PRISM_BINARY (default build/ci/apps/prism), PRISM_SOAK_SECONDS (600), PRISM_SOAK_WARMUP (60),
# PRISM_SOAK_INTERVAL (5), PRISM_SOAK_BACKEND (vulkan:llvmpipe), PRISM_SOAK_SCENE (builtin:sphere),
# PRISM_SOAK_SIZE (160x120), PRISM_SOAK_LIMIT_PCT (5).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-bench/results/cpu2/viewer-soak-lavapipe.json}
prism=${PRISM_BINARY:-build/ci/apps/prism}
seconds=${PRISM_SOAK_SECONDS:-600}
warmup=${PRISM_SOAK_WARMUP:-60}
interval=${PRISM_SOAK_INTERVAL:-5}
backend=${PRISM_SOAK_BACKEND:-vulkan:llvmpipe}
scene=${PRISM_SOAK_SCENE:-builtin:sphere}
size=${PRISM_SOAK_SIZE:-160x120}
limit=${PRISM_SOAK_LIMIT_PCT:-5}
[ -x "$prism" ] || { echo "soak_viewer.sh: $prism: not built (cmake --preset ci && cmake --build --preset ci)" >&2; exit 1; }
command -v xvfb-run >/dev/null || { echo "soak_viewer.sh: xvfb-run missing (apt-get install xvfb xauth)" >&2; exit 1; }
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"; chmod 700 "$XDG_RUNTIME_DIR"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The shell writes its PID and execs prism, so the PID sampled is the viewer's own, not xvfb-run's.
xvfb-run -a sh -c 'echo $$ >"$0"; exec "$@"' "$work/pid" "$prism" view --scene "$scene" --backend "$backend" \
  --width "${size%x*}" --height "${size#*x}" --no-vsync --keys 0:M --seconds "$seconds" >"$work/log" 2>&1 &
runner=$!
for _ in $(seq 100); do [ -s "$work/pid" ] && break; sleep 0.1; done
pid=$(cat "$work/pid")
echo "soak: prism view (pid $pid) on $backend for $seconds s, VmRSS every $interval s, warm-up $warmup s"

started=$(date +%s%N)
samples=()
while [ -r "/proc/$pid/status" ]; do
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$rss" ] || break
  t=$(( ($(date +%s%N) - started) / 1000000 ))
  samples+=("$t $rss")
  sleep "$interval"
done
status=0
wait "$runner" || status=$?

frames=$(sed -n 's/^  rendered \([0-9]*\) frames in .*/\1/p' "$work/log")
device=$(sed -n 's/^prism view: .* on \(.*\)$/\1/p' "$work/log" | head -1)
printf '%s\n' "${samples[@]}" >"$work/samples"
# Warm-up ends at the first sample at or after $warmup s; growth is the largest later sample against it.
read -r baseline peak last count < <(awk -v w=$((warmup * 1000)) '
  $1 >= w { if (b == "") b = $2; if ($2 > p) p = $2; l = $2; n++ }
  END { print (b == "" ? 0 : b), (p == "" ? 0 : p), (l == "" ? 0 : l), n + 0 }' "$work/samples")
growth=$(awk -v b="$baseline" -v p="$peak" 'BEGIN { printf "%.2f", (b > 0 ? (p - b) * 100 / b : 0) }')
pass=$(awk -v g="$growth" -v l="$limit" -v s="$status" -v f="${frames:-0}" -v n="$count" \
  'BEGIN { print ((s == 0 && f > 0 && n >= 2 && g <= l) ? "true" : "false") }')

mkdir -p "$(dirname "$out")"
{
  echo "{"
  echo "  \"kind\": \"viewer-soak\","
  echo "  \"commit\": \"$(git rev-parse --short=12 HEAD)$(git diff --quiet HEAD -- . ':!bench/results' || echo -dirty)\","
  echo "  \"date\": \"$(date -u +%Y-%m-%dT%H:%M:%SZ)\","
  echo "  \"host\": {\"cpu\": \"$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)\", \"threads\": $(nproc)},"
  echo "  \"device\": \"${device//\"/\\\"}\","
  echo "  \"command\": \"xvfb-run -a prism view --scene $scene --backend $backend --width ${size%x*} --height ${size#*x} --no-vsync --keys 0:M --seconds $seconds\","
  echo "  \"exit_code\": $status,"
  echo "  \"seconds\": $seconds, \"warmup_seconds\": $warmup, \"sample_interval_seconds\": $interval,"
  echo "  \"frames_rendered\": ${frames:-0},"
  echo "  \"rss_after_warmup_kib\": $baseline, \"rss_max_after_warmup_kib\": $peak, \"rss_last_kib\": $last,"
  echo "  \"max_growth_after_warmup_pct\": $growth, \"limit_pct\": $limit, \"pass\": $pass,"
  echo "  \"samples\": ["
  awk '{ printf "%s    {\"t_ms\": %d, \"rss_kib\": %d}", (NR > 1 ? ",\n" : ""), $1, $2 } END { print "" }' "$work/samples"
  echo "  ]"
  echo "}"
} >"$out"
echo "soak: ${frames:-0} frames, VmRSS ${baseline} KiB after warm-up, max ${peak} KiB (+${growth}%), last ${last} KiB," \
     "exit $status: $([ "$pass" = true ] && echo PASS || echo FAIL) (limit +${limit}%) -> $out"
[ "$pass" = true ] || { tail -5 "$work/log" >&2; exit 1; }
