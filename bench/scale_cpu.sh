#!/usr/bin/env bash
# The mechanics of split renders on a machine without a GPU (docs/scaling.md): one frame of the bunny split into
# tiles over workers in one process and over MPI ranks, a mixed cpu + OpenCL (PoCL) run, and a short turntable
# taken frame by frame by two ranks, each against the one-process render of the same frame or sequence. Every image
# is checked byte for byte against it. On a machine of few cores the workers share them, so the speedups say what
# the scheduler costs, not what more devices give (bench/scale_gpu.sh measures that on GPUs).
#   PRISM_BUILD (default build/ci), PRISM_DATA (default ../shared/scenes), OUT (default bench/results/cpu2/scale)
#   PRISM_SCALE_SIZE (default 640x360), PRISM_SCALE_TILE (default 64), PRISM_SCALE_FRAMES (default 12)
set -uo pipefail
build=${PRISM_BUILD:-build/ci}
data=${PRISM_DATA:-../shared/scenes}
out=${OUT:-bench/results/cpu2/scale}
size=${PRISM_SCALE_SIZE:-640x360}
tile=${PRISM_SCALE_TILE:-64}
frames=${PRISM_SCALE_FRAMES:-12}
prism=$build/apps/prism
mpirun=(mpirun --allow-run-as-root --oversubscribe)
mkdir -p "$out"
common=(-q --data-dir "$data" --scene builtin:bunny --width "${size%x*}" --height "${size#*x}" --depth 8
        --bvh-layout stack)
same() {
  if cmp -s "$out/$1.png" "$2"; then echo "  bit-identical to $1: $2"; else echo "  DIFFERS from $1: $2"; fi
}
run() {   # run NAME [launcher...] -- prism arguments
  local name=$1; shift
  local launcher=()
  while [ "$1" != "--" ]; do launcher+=("$1"); shift; done
  shift
  echo "== $name"
  "${launcher[@]}" "$prism" render "${common[@]}" "$@" --out "$out/$name.png" --stats "$out/$name.json" \
    || echo "  failed"
}
run cpu -- --backend cpu
run cpu-tiles -- --backend cpu,cpu --tile-size "$tile"
same cpu "$out/cpu-tiles.png"
run mpi-2-cpu "${mpirun[@]}" -np 2 -- --backend cpu --tile-size "$tile"
same cpu "$out/mpi-2-cpu.png"
run mpi-3-cpu "${mpirun[@]}" -np 3 -- --backend cpu --tile-size "$tile"
same cpu "$out/mpi-3-cpu.png"
run opencl -- --backend opencl:pocl
run cpu-opencl -- --backend cpu,opencl:pocl --tile-size "$tile"
# Bit-identical to one backend only where the two backends' float math agrees on every pixel they share.
same opencl "$out/cpu-opencl.png"
same cpu "$out/cpu-opencl.png"
echo "== turntable, $frames frames: one process, then two ranks taking frames"
sequence=(-q --data-dir "$data" --scene builtin:bunny --width 320 --height 180 --depth 8 --bvh-layout stack
          --frames "0-$((frames - 1))" --turntable 2 --fps 6)
mkdir -p "$out/turntable" "$out/turntable-mpi"
"$prism" render "${sequence[@]}" --backend cpu --out "$out/turntable/f%04d.png" --stats "$out/turntable-cpu.json"
"${mpirun[@]}" -np 2 "$prism" render "${sequence[@]}" --backend cpu --out "$out/turntable-mpi/f%04d.png" \
  --stats "$out/turntable-mpi-2-cpu.json"
diff -rq "$out/turntable" "$out/turntable-mpi" > /dev/null && echo "  turntable frames bit-identical" \
  || echo "  turntable frames DIFFER"
rm -rf "$out/turntable" "$out/turntable-mpi" "$out"/*.png
plot=(python3 bench/plot_bench.py)
[ -x /usr/bin/python3 ] && plot=(/usr/bin/python3 bench/plot_bench.py)
"${plot[@]}" --baseline "$out/cpu.json" --baseline "$out/turntable-cpu.json" "$out/cpu-tiles.json" \
  "$out/mpi-2-cpu.json" "$out/mpi-3-cpu.json" "$out/cpu-opencl.json" "$out/turntable-mpi-2-cpu.json" \
  --out "$out/scale.png"
