#!/usr/bin/env bash
# The GPU session in one command, run from the repository root on the GPU machine (docs/results.md says how the
# build, runtime libraries and scenes get there). Writes results and logs under $OUT (default bench/results/gpu).
#   PRISM_BUILD: build folder with apps/prism and tests/prism_tests (default build-gpu)
#   PRISM_DATA:  scenes folder laid out like ../shared/scenes (default .device-data/scenes)
#   PRISM_TAG:   suffix of the result files (default: the GPU's name)
#   PRISM_SKIP_TESTS / PRISM_SKIP_SEED_TABLE / PRISM_SKIP_BANDWIDTH=1 skip a part; PRISM_CPU_BENCH=0 skips the
#   host-CPU table; PRISM_VULKAN_AB=1 adds Vulkan's fixed-grid and device-address variants.
#   PRISM_VIEW_BENCH=1: also bench/view_gpu.sh (the viewer's display paths, offscreen through NVIDIA's EGL)
#   PRISM_RAYS_SIZES="1920x1080 1920x1080 3840x2160": also issue 19's ray sets at these sizes (a size listed twice
#   runs twice), beside tinybvh's kernel when PRISM_TINYBVH_KERNELS names a tinybvh checkout
set -uo pipefail
build=${PRISM_BUILD:-build-gpu}
data=${PRISM_DATA:-.device-data/scenes}
out=${OUT:-bench/results/gpu}
mkdir -p "$out"
export PRISM_SCENES_DIR=$PWD/$data PRISM_BINARY=$PWD/$build/apps/prism
# The OpenCL and Vulkan tests run on the GPU here (in CI: PoCL and lavapipe).
export PRISM_TEST_OPENCL_DEVICE=${PRISM_TEST_OPENCL_DEVICE:-opencl:nvidia} PRISM_TEST_VULKAN_DEVICE=${PRISM_TEST_VULKAN_DEVICE:-vulkan:nvidia}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)} XDG_CACHE_HOME=${XDG_CACHE_HOME:-$(mktemp -d)}
chmod 700 "$XDG_RUNTIME_DIR"
tag=${PRISM_TAG:-$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1 | tr ' ' '-' | tr -cd 'A-Za-z0-9-')}
tag=${tag:-gpu}
prism=$build/apps/prism
# The Vulkan tests run with the Khronos validation layer; a GPU machine without it gets the Debian build carried
# along as $build/vklayer/ (libVkLayer_khronos_validation.so.gz + its json).
if [ -f "$build/vklayer/libVkLayer_khronos_validation.so.gz" ]; then
  mkdir -p /tmp/prism-vklayer && gunzip -c "$build/vklayer/libVkLayer_khronos_validation.so.gz" \
    > /tmp/prism-vklayer/libVkLayer_khronos_validation.so
  sed 's|"library_path": "[^"]*"|"library_path": "/tmp/prism-vklayer/libVkLayer_khronos_validation.so"|' \
    "$build/vklayer/VkLayer_khronos_validation.json" > /tmp/prism-vklayer/VkLayer_khronos_validation.json
  export VK_LAYER_PATH=/tmp/prism-vklayer
fi
step() { echo; echo "== $* ($(date -u +%H:%M:%S))"; }

step info
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>&1 | tee "$out/nvidia-smi.txt"
$prism info | tee "$out/info-$tag.txt"

if [ "${PRISM_SKIP_TESTS:-0}" != 1 ] && [ ! -x "$build/tests/prism_tests" ]; then
  step "GPU tests: skipped, $build/tests/prism_tests is not here (bench/pack_gpu_call.sh with PRISM_PACK_TESTS=0)"
elif [ "${PRISM_SKIP_TESTS:-0}" != 1 ]; then
  step "GPU tests (CUDA, OpenCL and Vulkan on the device, Embree oracle)"
  $build/tests/prism_tests --gtest_filter="${PRISM_TEST_FILTER:-*Cuda*:*cuda*:*OpenCL*:*Opencl*:*opencl*:*Vulkan*:*vulkan*}" \
    2>&1 | tee "$out/tests-$tag.log" | grep -E '^\[  (PASSED|FAILED|SKIPPED) |^\[  FAILED|tests ran'
fi

backends=${PRISM_BACKENDS:-cuda,opencl:nvidia,vulkan:nvidia}
if [ "${PRISM_SKIP_SEED_TABLE:-0}" != 1 ]; then
step "seed table at the seed's setting (about 100,000 primary rays)"
$prism bench --data-dir "$data" --backends "$backends" --seed-setting --depth 8 --runs 10 --warmup 2 \
  --json "$out/seed-table-$tag-seed-setting.json"
step "seed table at 1920x1080, depth 8"
$prism bench --data-dir "$data" --backends "$backends" --width 1920 --height 1080 --depth 8 --runs 10 --warmup 2 \
  --json "$out/seed-table-$tag-1080p.json"
fi
if [ "${PRISM_VULKAN_AB:-0}" = 1 ]; then
  # What Vulkan's launch choices cost (docs/vulkan.md): the fixed grid instead of indirect dispatch, and buffer
  # device addresses instead of descriptors, each against the default run of the table above.
  step "Vulkan at 1920x1080 with the fixed grid (PRISM_VULKAN_DISPATCH=fixed)"
  PRISM_VULKAN_DISPATCH=fixed $prism bench --data-dir "$data" --backends vulkan:nvidia --width 1920 --height 1080 \
    --depth 8 --runs 10 --warmup 2 --json "$out/vulkan-$tag-fixed-dispatch-1080p.json"
  step "Vulkan at the seed's setting with the fixed grid (PRISM_VULKAN_DISPATCH=fixed)"
  PRISM_VULKAN_DISPATCH=fixed $prism bench --data-dir "$data" --backends vulkan:nvidia --seed-setting --depth 8 \
    --runs 10 --warmup 2 --json "$out/vulkan-$tag-fixed-dispatch-seed-setting.json"
  step "Vulkan at 1920x1080 through buffer device addresses (PRISM_VULKAN_ADDRESSING=addresses)"
  PRISM_VULKAN_ADDRESSING=addresses $prism bench --data-dir "$data" --backends vulkan:nvidia --width 1920 \
    --height 1080 --depth 8 --runs 10 --warmup 2 --json "$out/vulkan-$tag-addresses-1080p.json"
fi
if [ "${PRISM_CPU_BENCH:-1}" = 1 ]; then
  step "the same on the host CPU (cpu backend)"
  $prism bench --data-dir "$data" --backends cpu,cpu-ref --width 1920 --height 1080 --depth 8 --runs 3 --warmup 1 \
    --json "$out/seed-table-$tag-host-cpu-1080p.json"
fi
if [ "${PRISM_SKIP_BANDWIDTH:-0}" != 1 ]; then
  step "bandwidth"
  # No --plot: the GPU machine may lack matplotlib; draw it afterwards with bench/plot_bench.py from the JSON.
  $prism bandwidth --json "$out/bandwidth-$tag.json" 2>&1 | tee "$out/bandwidth-$tag.txt"
fi
if [ -n "${PRISM_RAYS_SIZES:-}" ]; then
  # Issue 19's ray sets (docs/ray-queries.md): each mesh's primary and diffuse rays through `prism rays --bench` on
  # every GPU API, and through tinybvh's own kernel on the same rays where the build has bench/tinybvh_rays and
  # PRISM_TINYBVH_KERNELS names the checkout's folder of traverse.cl. A size listed twice is a second round: the
  # two tools run in turn, so a drift of the card's clocks shows as a difference between rounds, not between tools.
  meshes=${PRISM_RAYS_MESHES:-stanford/bunny.ply stanford/dragon.ply.gz}
  tinybvh=$build/bench/tinybvh_rays
  declare -A round
  for size in $PRISM_RAYS_SIZES; do
    round[$size]=$(( ${round[$size]:-0} + 1 ))
    width=${size%x*} height=${size#*x} r=r${round[$size]}
    for mesh in $meshes; do
      name=$(basename "${mesh%%.*}")
      step "ray sets: $name at $size, round $r"
      if [ -x "$tinybvh" ] && [ -n "${PRISM_TINYBVH_KERNELS:-}" ]; then
        $tinybvh --scene "$data/$mesh" --kernels "$PRISM_TINYBVH_KERNELS" --width "$width" --height "$height" \
          --json "$out/tinybvh-$name-$size-$r.json" 2>&1 | tee "$out/tinybvh-$name-$size-$r.log" | grep -v '^prism:'
      fi
      $prism rays --bench --scene "$data/$mesh" --backends "$backends" --width "$width" --height "$height" \
        --json "$out/prism-$name-$size-$r.json" 2>&1 | tee "$out/prism-$name-$size-$r.log" | grep -v '^prism:'
    done
  done
fi
if [ "${PRISM_VIEW_BENCH:-0}" = 1 ]; then
  # prism view --headless (no X server there); PRISM_VIEW_* select scene, size, frames, backends.
  step "prism view: display by interop, by host copy, and the render alone (bench/view_gpu.sh)"
  PRISM_BUILD=$build PRISM_DATA=$data OUT=$out PRISM_TAG=$tag bash bench/view_gpu.sh
fi
step done
