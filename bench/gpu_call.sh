#!/usr/bin/env bash
# One GPU call, run from the repository root on the GPU machine after `source .gpu-runtime/env.sh`: unpacks
# bench/pack_gpu_call.sh's payload, lays the scenes where the tests look for them, runs bench/run_gpu.sh (tests,
# seed tables, bandwidth, issue 19's ray sets beside tinybvh), on an H200 also one frame under Nsight Compute, and
# leaves everything as one archive, $OUT/results.tar.gz (a call brings back at most 8 files).
#   SIZES: the ray sets' sizes (default "1920x1080 1920x1080 3840x2160": two rounds at 1080p, one at 4K; "": none)
#   Two calls when the payload has no room for everything (docs/results.md, "Reproducing on a GPU machine"): one
#   packed with PRISM_PACK_TESTS=0 that measures (and runs the A/B), one packed without a tinybvh checkout, run
#   with PRISM_SKIP_SEED_TABLE=1 PRISM_SKIP_BANDWIDTH=1 SIZES="" NCU_BEFORE_S=0, that runs the GPU tests. An A/B
#   of several builds does not fit beside the full run in one call's 10 minutes: the same settings with
#   AB_BEFORE_S=600 and AB_BUILDS run it alone, on the measuring call's payload.
#   NCU_BEFORE_S / NCU_TIMEOUT_S: profile only if the call is younger than this (default 420 s), for at most this
#   long (default 140 s); the run above took 5-6 minutes on an H100
#   AB_BUILDS="LABEL=BINARY ...": afterwards bench/ab_builds.sh on these builds (bench/pack_gpu_call.sh's
#   PRISM_PACK_BUILDS packs them as build-LABEL/apps/prism; main's is build-gpu/apps/prism), into ab/ of the archive,
#   if the call is younger than AB_BEFORE_S (default 400 s)
set -uo pipefail
root=$PWD
results=$(mktemp -d)
start=$(date +%s)
elapsed() { echo $(($(date +%s) - start)); }

tar -xJf .gpu-carry/payload.tar.xz && gzip -1 .device-data/scenes/stanford/dragon.ply || exit 1
# docs/examples/spot-lights.json names ../shared/scenes, and the tests find docs/ under the source folder they were
# built in (/work/main): both are laid here when the machine has neither.
mkdir -p ../shared && ln -sfn "$root/.device-data/scenes" ../shared/scenes
[ -e /work/main/docs ] || { mkdir -p /work && ln -sfn "$root" /work/main; }
[ -e /work/shared/scenes ] || { mkdir -p /work/shared && ln -sfn "$root/.device-data/scenes" /work/shared/scenes; }
gpu=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1)
echo "unpacked in $(elapsed) s; GPU: $gpu"

tinybvh_kernels=.device-data/tinybvh
[ -d "$tinybvh_kernels" ] || tinybvh_kernels=
OUT=$results PRISM_CPU_BENCH=0 PRISM_RAYS_SIZES="${SIZES-1920x1080 1920x1080 3840x2160}" \
  PRISM_TINYBVH_KERNELS=$tinybvh_kernels bash bench/run_gpu.sh 2>&1 | tee "$results/run.log" |
  grep -vE '^prism: (rays|loading|building)'

if [[ $gpu == *H200* ]] && [ "$(elapsed)" -lt "${NCU_BEFORE_S:-420}" ]; then
  # The first four depths of the dragon's 1080p frame, every traversal, miss and shade launch
  # (bench/ncu_stage_table.py reads the raw page with the frame's --stats).
  ncu=$(command -v ncu || ls /usr/local/cuda/bin/ncu /opt/nvidia/nsight-compute/*/ncu 2>/dev/null | head -1)
  mkdir -p "$results/ncu"
  "$ncu" --version > "$results/ncu/ncu-version.txt" 2>&1
  echo "== Nsight Compute, one frame ($(date -u +%H:%M:%S))"
  timeout "${NCU_TIMEOUT_S:-140}" "$ncu" --clock-control none --set full --launch-count 16 \
    -k regex:'prism_cuda_(intersect|shade|shadow|miss|occlude)' -o /tmp/frame build-gpu/apps/prism render \
    --data-dir .device-data/scenes --scene builtin:dragon --backend cuda --width 1920 --height 1080 --depth 8 \
    --out /tmp/frame.png --stats "$results/ncu/frame-stats.json" > "$results/ncu/ncu.log" 2>&1
  echo "ncu exit $?"
  [ -f /tmp/frame.ncu-rep ] && "$ncu" --import /tmp/frame.ncu-rep --page raw --csv | gzip > "$results/ncu/frame-raw.csv.gz"
fi
if [ -n "${AB_BUILDS:-}" ] && [ "$(elapsed)" -lt "${AB_BEFORE_S:-400}" ]; then
  echo "== A/B of $AB_BUILDS ($(date -u +%H:%M:%S))"
  OUT=$results/ab bash bench/ab_builds.sh $AB_BUILDS
fi
echo "== done after $(elapsed) s"
tar -czf "${OUT:-$root}/results.tar.gz" -C "$results" .
