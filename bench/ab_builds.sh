#!/usr/bin/env bash
# Two or more builds of prism in turn on one GPU machine: issue 19's ray sets (`prism rays --bench`) and the
# builtin frames (`prism bench`), round after round, so that a drift of the card's clocks shows as a difference
# between rounds, not between builds. Run from the repository root on the GPU machine after
# `source .gpu-runtime/env.sh`, with the scenes where bench/gpu_call.sh lays them.
#   bash bench/ab_builds.sh LABEL=PRISM_BINARY ...   (e.g. main=build-gpu/apps/prism probe=build-probe/apps/prism)
#   OUT: results folder (default bench/results/gpu/ab); ROUNDS (default 2); SIZE (default 1920x1080)
#   PRISM_DATA (default .device-data/scenes); PRISM_RAYS_MESHES (default stanford/bunny.ply stanford/dragon.ply.gz)
#   PRISM_AB_SCENES: the frames' scenes (default builtin:dragon,builtin:bunny; empty: no frames)
#   PRISM_BACKENDS (default cuda,opencl:nvidia,vulkan:nvidia)
# Writes LABEL-MESH-rN.json / .log (ray sets) and LABEL-frames-rN.json / .log; bench/ab_frames_table.py makes the
# frames' table.
set -uo pipefail
[ $# -ge 2 ] || { echo "usage: bench/ab_builds.sh LABEL=PRISM_BINARY LABEL=PRISM_BINARY..." >&2; exit 2; }
out=${OUT:-bench/results/gpu/ab}
data=${PRISM_DATA:-.device-data/scenes}
backends=${PRISM_BACKENDS:-cuda,opencl:nvidia,vulkan:nvidia}
size=${SIZE:-1920x1080}
scenes=${PRISM_AB_SCENES-builtin:dragon,builtin:bunny}
mkdir -p "$out"
for build in "$@"; do
  [ -x "${build#*=}" ] || { echo "ab_builds: ${build#*=}: not an executable" >&2; exit 2; }
done
status=0
for round in $(seq 1 "${ROUNDS:-2}"); do
  for build in "$@"; do
    label=${build%%=*} prism=${build#*=}
    for mesh in ${PRISM_RAYS_MESHES:-stanford/bunny.ply stanford/dragon.ply.gz}; do
      name=$(basename "${mesh%%.*}")
      "$prism" rays --bench --scene "$data/$mesh" --backends "$backends" --width "${size%x*}" --height "${size#*x}" \
        --json "$out/$label-$name-r$round.json" > "$out/$label-$name-r$round.log" 2>&1
      rc=$?; [ $rc = 0 ] || status=1
      echo "ab_builds: $label $name round $round: exit $rc"
    done
    if [ -n "$scenes" ]; then
      "$prism" bench --data-dir "$data" --scenes "$scenes" --backends "$backends" --width "${size%x*}" \
        --height "${size#*x}" --depth 8 --runs 10 --warmup 2 --json "$out/$label-frames-r$round.json" \
        > "$out/$label-frames-r$round.log" 2>&1
      rc=$?; [ $rc = 0 ] || status=1
      echo "ab_builds: $label frames round $round: exit $rc"
    fi
  done
done
exit $status
