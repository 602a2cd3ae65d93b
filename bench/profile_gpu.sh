#!/usr/bin/env bash
# Profiles the CUDA backend on the GPU machine (run from the repository root after bench/run_gpu.sh's setup):
# Nsight Compute on the dragon's deepest intersect launch and a shade launch at 1920x1080, and compute-sanitizer
# memcheck + racecheck on a small frame. Output under $OUT (default bench/results/gpu).
set -uo pipefail
build=${PRISM_BUILD:-build-gpu}
data=${PRISM_DATA:-.device-data/scenes}
out=${OUT:-bench/results/gpu}
mkdir -p "$out"
prism=$build/apps/prism
ncu=$(command -v ncu || ls /usr/local/cuda/bin/ncu /opt/nvidia/nsight-compute/*/ncu 2>/dev/null | head -1)
sanitizer=$(command -v compute-sanitizer || ls /usr/local/cuda/bin/compute-sanitizer 2>/dev/null | head -1)
frame="render --data-dir $data --scene builtin:dragon --backend cuda --width 1920 --height 1080 --depth 8 --out /tmp/profile.png"

echo "== Nsight Compute: intersect at depth 5 and shade at depth 3 (launches counted from the frame's start)"
# A frame launches generate, then per depth intersect/miss/shade/shadow: intersect of depth d is launch 2 + 4d.
"$ncu" --clock-control none --kernel-name regex:prism_cuda_intersect --launch-skip 5 --launch-count 1 \
  --section SpeedOfLight --section Occupancy --section LaunchStats --section MemoryWorkloadAnalysis \
  --section WarpStateStats $prism $frame 2>&1 | grep -v "^==PROF==" | tee "$out/ncu-dragon-intersect.txt" | tail -60
"$ncu" --clock-control none --kernel-name regex:prism_cuda_shade --launch-skip 3 --launch-count 1 \
  --section SpeedOfLight --section Occupancy --section LaunchStats $prism $frame 2>&1 | grep -v "^==PROF==" \
  > "$out/ncu-dragon-shade.txt"
grep -E "Duration|Registers Per|Achieved Occupancy|Theoretical Occupancy|Local Memory|Compute \(SM\) Throughput|Memory Throughput" \
  "$out/ncu-dragon-shade.txt"

echo "== compute-sanitizer"
small="render --data-dir $data --scene builtin:bunny --backend cuda --width 96 --height 72 --depth 6 --out /tmp/sanitized.png"
for tool in memcheck racecheck; do
  "$sanitizer" --tool $tool --error-exitcode 3 $prism $small > "$out/compute-sanitizer-$tool.txt" 2>&1
  echo "$tool: exit $? — $(grep -E 'ERROR SUMMARY|RACECHECK SUMMARY' "$out/compute-sanitizer-$tool.txt" | tail -1)"
done
