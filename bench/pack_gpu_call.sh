#!/usr/bin/env bash
# Packs what one GPU call needs beside the working tree into .gpu-carry/payload.tar.xz (git-ignored): the binaries
# stripped, the scenes the GPU tests and benchmarks read, and tinybvh's kernels when a checkout is named. A call
# carries its tracked files, .gpu-runtime (../shared/tools/gpu/pack-runtime.sh) and this payload, 64 MiB in all:
# the build folder and the scenes as they are do not fit, and a run without the cube map renders the builtin
# scenes under the procedural sky (other images, three failed tests). bench/gpu_call.sh unpacks it there.
#   bench/pack_gpu_call.sh [build folder, default build-gpu] [tinybvh checkout]
#   PRISM_PACK_BUILDS="LABEL=PRISM_BINARY ...": other builds of prism for an A/B, packed as build-LABEL/apps/prism
#   (xz finds most of a second build in the first: about 0.5 MB each); bench/gpu_call.sh's AB_BUILDS runs them.
#   PRISM_PACK_TESTS=0: leave out the GPU tests (tests/prism_tests and the scenes only they read: 6.5 of 17.7 MiB),
#   for a call that measures; bench/run_gpu.sh then skips the tests. The results the repository keeps grow the
#   tracked files a call carries by about 1 MiB a GPU session, so a call with probes soon needs the room.
set -euo pipefail
build=${1:-build-gpu}
tinybvh=${2:-}
scenes=${PRISM_SCENES_SOURCE:-../shared/scenes}
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT

with_tests=${PRISM_PACK_TESTS:-1}
binaries=apps/prism
[ -z "$tinybvh" ] || binaries="$binaries bench/tinybvh_rays"  # with its kernels only
[ "$with_tests" = 0 ] || binaries="$binaries tests/prism_tests"
for binary in $binaries; do
  [ -x "$build/$binary" ] || continue
  # Under build-gpu/ whatever the folder here: bench/run_gpu.sh's default there.
  mkdir -p "$stage/build-gpu/$(dirname $binary)"
  strip -o "$stage/build-gpu/$binary" "$build/$binary"
done
[ -x "$stage/build-gpu/apps/prism" ] || { echo "pack_gpu_call: $build/apps/prism is not built" >&2; exit 1; }
folders=(build-gpu)
for other in ${PRISM_PACK_BUILDS:-}; do
  label=${other%%=*} binary=${other#*=}
  [ -x "$binary" ] || { echo "pack_gpu_call: $binary (build $label) is not built" >&2; exit 1; }
  mkdir -p "$stage/build-$label/apps"
  strip -o "$stage/build-$label/apps/prism" "$binary"
  folders+=("build-$label")
done

# The scenes: the seed table's meshes and cube map, the ray sets' meshes, and every scene the GPU tests load
# (tests/test_backend_contract.cpp's Agreement cases; docs/examples/spot-lights.json reaches TwoSidedPlane).
data=$stage/.device-data/scenes
scene_paths="stanford/bunny.ply stanford/dragon.ply.gz env/cubemap-miramar"
[ "$with_tests" = 0 ] || scene_paths="$scene_paths mcguire/conference gltf/BoxTextured gltf/GlassVaseFlowers
    gltf/IridescenceSuzanne gltf/MetalRoughSpheresNoTextures gltf/TransmissionTest gltf/TwoSidedPlane"
for path in $scene_paths; do
  mkdir -p "$data/$(dirname $path)"
  cp -r "$scenes/$path" "$data/$path"
done
chmod -R u+w "$stage"
# xz packs the plain text tighter than gzip does (the dragon 8.0 -> 5.4 MB): bench/gpu_call.sh gzips it again.
gunzip "$data/stanford/dragon.ply.gz"
if [ -n "$tinybvh" ]; then
  mkdir -p "$stage/.device-data/tinybvh"
  cp "$tinybvh"/*.cl "$stage/.device-data/tinybvh/"
fi

mkdir -p .gpu-carry
# The other builds right after main's, within xz's window of it.
tar -cf - -C "$stage" "${folders[@]}" .device-data | xz -9e -T2 > .gpu-carry/payload.tar.xz
mib() { awk -v b="$1" 'BEGIN {printf "%.1f", b / 1048576}'; }
tracked=$(git ls-files -z | xargs -0 stat -c %s | awk '{s += $1} END {print s}')
runtime=$(find .gpu-runtime -type f -exec stat -c %s {} + 2>/dev/null | awk '{s += $1} END {print s + 0}')
payload=$(stat -c %s .gpu-carry/payload.tar.xz)
total=$((tracked + runtime + payload))
echo "pack_gpu_call: payload $(mib $payload) MiB; with the tracked files ($(mib $tracked)) and .gpu-runtime" \
  "($(mib $runtime)) a call carries $(mib $total) MiB (at most 62)"
# The device tool counts a call's files with more than their bytes: 63.2 MiB by this sum was refused as over 64, 61.4
# passed (2026-12-07). Hence the margin.
[ "$total" -lt $((62 * 1048576)) ] || { echo "pack_gpu_call: over the 62 MiB a call safely carries" >&2; exit 1; }
