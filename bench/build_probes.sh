#!/usr/bin/env bash
# Builds prism once per kernel probe for an A/B on the GPU machine: each LABEL's patch applied to a worktree of HEAD
# under $PROBES (default ../probes/LABEL), built as main's GPU build is, and prints the two lines the GPU call needs
# (bench/pack_gpu_call.sh's PRISM_PACK_BUILDS and bench/gpu_call.sh's AB_BUILDS; docs/results.md).
#   bench/build_probes.sh LABEL=PATCH ...   (e.g. fma=bench/results/cpu2/ab-da2d46f-03f7c8b-slab-fma/slab-fma-03f7c8b.patch)
#   PRISM_TINYBVH_DIR: passed to cmake as main's build-gpu has it (optional); CUDA for sm_90, Release.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: bench/build_probes.sh LABEL=PATCH ..." >&2; exit 2; }
root=$(git rev-parse --show-toplevel)
probes=$(realpath -m "${PROBES:-$root/../probes}")
pack="" ab="main=build-gpu/apps/prism"
for probe in "$@"; do
  label=${probe%%=*} patch=$(realpath "${probe#*=}")
  tree=$probes/$label
  if [ ! -d "$tree" ]; then
    git -C "$root" worktree add -q --detach "$tree" HEAD
    git -C "$tree" apply "$patch"
  elif [ "$(git -C "$tree" rev-parse HEAD)" != "$(git -C "$root" rev-parse HEAD)" ]; then
    # A probe is HEAD plus its patch: an older worktree would measure older kernels under the probe's name.
    echo "build_probes: $tree is not at HEAD; remove it (git worktree remove --force $tree)" >&2
    exit 1
  fi
  cmake -S "$tree" -B "$tree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CUDA_ARCHITECTURES=90 \
    ${PRISM_TINYBVH_DIR:+-DPRISM_TINYBVH_DIR=$PRISM_TINYBVH_DIR} > "$tree/cmake.log"
  ninja -C "$tree/build" prism > "$tree/build.log" || { echo "build_probes: $label failed: $tree/build.log" >&2; exit 1; }
  echo "build_probes: $label built ($(git -C "$tree" diff --stat | tail -1))"
  pack="$pack $label=$tree/build/apps/prism"
  ab="$ab $label=build-$label/apps/prism"
done
echo "PRISM_PACK_BUILDS=\"${pack# }\""
echo "AB_BUILDS=\"$ab\""
