#!/usr/bin/env bash
# Issue 20's one-GPU measurement: one frame split into tiles over a CUDA device and the host's CPU cores, against
# CUDA alone, and a turntable sequence over the same workers. Run from the repository root on the GPU machine
# (docs/results.md, "Reproducing on a GPU machine", says how the build and the scenes get there). Writes the
# --stats JSON and the logs under $OUT (default bench/results/scale-gpu); every image is checked bit for bit
# against the CUDA-alone render of the same frame.
#   PRISM_BUILD: build folder with apps/prism (default build-gpu)
#   PRISM_DATA:  scenes folder laid out like ../shared/scenes (default .device-data/scenes)
#   PRISM_SCALE_SIZE: WIDTHxHEIGHT (default 3840x2160); PRISM_SCALE_TILE: tile side (default 256)
#   PRISM_SCALE_FRAMES: frames of the turntable (default 120)
# Under mpirun (when the machine has one) the same frame also runs as ranks: cuda on rank 0, cpu ranks beside it.
# On a host of several GPUs, cuda:all splits the frame (and the turntable's frames) over all of them: the speedup
# over one GPU is cuda.json's frame_ms over cuda-all.json's (turntable-cuda.json's sequence_ms likewise).
set -uo pipefail
build=${PRISM_BUILD:-build-gpu}
data=${PRISM_DATA:-.device-data/scenes}
out=${OUT:-bench/results/scale-gpu}
size=${PRISM_SCALE_SIZE:-3840x2160}
tile=${PRISM_SCALE_TILE:-256}
frames=${PRISM_SCALE_FRAMES:-120}
width=${size%x*}
height=${size#*x}
prism=$build/apps/prism
mkdir -p "$out"
cores=$(nproc)
common=(--data-dir "$data" --scene builtin:dragon --width "$width" --height "$height" --depth 8 --bvh-layout stack)
step() { echo; echo "== $* ($(date -u +%H:%M:%S))"; }
same() {   # same image as CUDA alone, byte for byte
  if cmp -s "$out/cuda.png" "$1"; then echo "bit-identical to cuda alone: $1"; else echo "DIFFERS from cuda alone: $1"; fi
}

step "CUDA alone (whole frame, then the same frame as tiles on one device)"
$prism render --backend cuda "${common[@]}" --out "$out/cuda.png" --stats "$out/cuda.json" | tee "$out/cuda.log"
$prism render --backend cuda,cuda:0 "${common[@]}" --tile-size "$tile" --out "$out/cuda-tiles.png" \
  --stats "$out/cuda-tiles.json" | tee "$out/cuda-tiles.log"
same "$out/cuda-tiles.png"

step "CUDA + the host CPU ($cores threads) in one process, tiles of $tile"
$prism render --backend cuda,cpu "${common[@]}" --tile-size "$tile" --out "$out/cuda-cpu.png" \
  --stats "$out/cuda-cpu.json" | tee "$out/cuda-cpu.log"
same "$out/cuda-cpu.png"

step "CUDA + the host CPU, tiles of $((tile / 2)) (smaller tiles: finer balance, more launches)"
$prism render --backend cuda,cpu "${common[@]}" --tile-size $((tile / 2)) --out "$out/cuda-cpu-small.png" \
  --stats "$out/cuda-cpu-small.json" | tee "$out/cuda-cpu-small.log"
same "$out/cuda-cpu-small.png"

step "cuda:all (every CUDA device of the host)"
$prism render --backend cuda:all "${common[@]}" --tile-size "$tile" --out "$out/cuda-all.png" \
  --stats "$out/cuda-all.json" | tee "$out/cuda-all.log"
same "$out/cuda-all.png"

if command -v mpirun > /dev/null; then
  step "mpirun -np 3: cuda on rank 0, two cpu ranks (each runs a thread per core)"
  mpirun --allow-run-as-root --oversubscribe -np 3 $prism render --backend cuda,cpu,cpu "${common[@]}" \
    --tile-size "$tile" --out "$out/mpi-cuda-cpu.png" --stats "$out/mpi-cuda-cpu.json" | tee "$out/mpi-cuda-cpu.log"
  same "$out/mpi-cuda-cpu.png"
else
  echo "no mpirun on this machine: the MPI runs are owed" | tee "$out/mpi-owed.txt"
fi

step "turntable, $frames frames at 1920x1080: CUDA alone, then CUDA + CPU taking frames"
mkdir -p "$out/turntable-cuda" "$out/turntable-cuda-cpu"
seq_common=(--data-dir "$data" --scene builtin:dragon --width 1920 --height 1080 --depth 8 --bvh-layout stack
            --frames "0-$((frames - 1))" --turntable 5 --fps 24)
$prism render --backend cuda "${seq_common[@]}" --out "$out/turntable-cuda/f%04d.png" \
  --stats "$out/turntable-cuda.json" | tee "$out/turntable-cuda.log"
$prism render --backend cuda,cpu "${seq_common[@]}" --out "$out/turntable-cuda-cpu/f%04d.png" \
  --stats "$out/turntable-cuda-cpu.json" | tee "$out/turntable-cuda-cpu.log"
diff -rq "$out/turntable-cuda" "$out/turntable-cuda-cpu" > /dev/null && echo "turntable frames bit-identical" \
  || echo "turntable frames DIFFER (the cpu frames use the CPU's float math: expected where FMA differs)"
gpus=$(nvidia-smi -L 2> /dev/null | grep -c '^GPU' || true)
if [ "${gpus:-0}" -gt 1 ]; then
  step "turntable on cuda:all ($gpus GPUs, each taking frames)"
  mkdir -p "$out/turntable-cuda-all"
  $prism render --backend cuda:all "${seq_common[@]}" --out "$out/turntable-cuda-all/f%04d.png" \
    --stats "$out/turntable-cuda-all.json" | tee "$out/turntable-cuda-all.log"
  diff -rq "$out/turntable-cuda" "$out/turntable-cuda-all" > /dev/null && echo "cuda:all turntable bit-identical" \
    || echo "cuda:all turntable DIFFERS from one GPU"
  rm -rf "$out/turntable-cuda-all"
fi
rm -rf "$out/turntable-cuda" "$out/turntable-cuda-cpu"   # 120 PNGs each: the JSON keeps the numbers
