#!/usr/bin/env bash
# `prism view` on the GPU machine: for each GPU backend, the dragon at 1920x1080 shown by buffer interop, by host
# copy, and not shown at all (the render alone), each run's --stats, and one summary JSON with the interop overhead
# against the render alone (docs/viewer.md, "Measuring on the H100"). Run from the repository root there, after
# `source .gpu-runtime/env.sh`; bench/run_gpu.sh calls it when PRISM_VIEW_BENCH=1. The machine has no X server:
# the viewer runs --headless, drawing into an offscreen framebuffer of NVIDIA's GL through EGL.
#   PRISM_BUILD          build folder with apps/prism (default build-gpu)
#   PRISM_DATA           scenes folder (default .device-data/scenes)
#   OUT                  results folder (default bench/results/gpu): view-<tag>.json, view/<tag>-*.json and logs
#   PRISM_TAG            suffix of the result files (default: the GPU's name)
#   PRISM_VIEW_BACKENDS  default cuda,opencl:nvidia,vulkan:nvidia
#   PRISM_VIEW_SCENE     default builtin:dragon;  PRISM_VIEW_SIZE default 1920x1080;  PRISM_VIEW_FRAMES default 200
#   PRISM_VIEW_DEPTH     default 8;  PRISM_VIEW_TIMEOUT: seconds allowed per run (default 240)
#   PRISM_VIEW_ALTERNATE blocks of --alternate-display for the interop and host-copy runs (default 10)
#   PRISM_VIEW_ABLATION  backends whose interop cost is also split into its two halves, the device copy alone and GL
#                        alone (PRISM_VIEW_ABLATE=copy|gl, apps/cmd_view.cpp; not with shared semaphores). Default cuda
#   PRISM_VIEW_PANEL     1: every run draws the on-screen panel (Dear ImGui) over the frame, to measure what it
#                        costs against a run without; default 0 (the frame alone, as the results before the panel)
#   PRISM_VIEW_ANY_GL=1  run even when GL is not NVIDIA's (to check this script on a machine without a GPU:
#                        PRISM_BUILD=build PRISM_DATA=../shared/scenes OUT=/tmp/view PRISM_VIEW_ANY_GL=1
#                        PRISM_VIEW_BACKENDS=vulkan:llvmpipe PRISM_VIEW_SIZE=160x90 PRISM_VIEW_FRAMES=5 ...)
set -uo pipefail
build=${PRISM_BUILD:-build-gpu}
data=${PRISM_DATA:-.device-data/scenes}
out=${OUT:-bench/results/gpu}
scene=${PRISM_VIEW_SCENE:-builtin:dragon}
size=${PRISM_VIEW_SIZE:-1920x1080}
width=${size%x*}
height=${size#*x}
frames=${PRISM_VIEW_FRAMES:-200}
depth=${PRISM_VIEW_DEPTH:-8}
run_limit=${PRISM_VIEW_TIMEOUT:-240}   # seconds per prism view run
backends=${PRISM_VIEW_BACKENDS:-cuda,opencl:nvidia,vulkan:nvidia}
alternate=${PRISM_VIEW_ALTERNATE:-10}
ablation=${PRISM_VIEW_ABLATION-cuda}
prism=$PWD/$build/apps/prism
target_ms=0.2   # issue 7: interop may add at most this much to a frame over the render alone
mkdir -p "$out/view"
export PRISM_VIEW_PANEL=${PRISM_VIEW_PANEL:-0}   # read by prism view itself; its --stats record "panel"
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)} XDG_CACHE_HOME=${XDG_CACHE_HOME:-$(mktemp -d)}
chmod 700 "$XDG_RUNTIME_DIR"
tag=${PRISM_TAG:-$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1 | tr ' ' '-' | tr -cd 'A-Za-z0-9-')}
tag=${tag:-gpu}
[ -x "$prism" ] || { echo "view_gpu: no $prism (PRISM_BUILD?)" >&2; exit 1; }

# Display timings mean nothing on llvmpipe: make sure GL is NVIDIA's before spending the time.
probe=$("$prism" view --headless --data-dir "$data" --scene builtin:sphere --backend cpu --width 64 --height 64 \
        --frames 1 2>&1)
gl=$(printf '%s\n' "$probe" | sed -n 's/^  offscreen [0-9x]*, //p' | head -1)
echo "== GL: ${gl:-none} "
if ! printf '%s' "$gl" | grep -qi nvidia && [ "${PRISM_VIEW_ANY_GL:-0}" != 1 ]; then
  echo "view_gpu: GL is not NVIDIA's (${gl:-no context}):" >&2
  printf '%s\n' "$probe" | tail -3 >&2
  exit 1
fi

# A top-level number of a --stats file (nlohmann::json dump(2): top-level keys are indented by two spaces), and a
# string of its "display" object, still JSON-escaped as written. No jq or python needed on the machine.
field() { sed -n "s/^  \"$2\": \\([-0-9.e+]*\\),\\{0,1\\}$/\\1/p" "$1" | head -1; }
alternating() { sed -n "/^  \"alternating\": {/,/^  }/ s/^    \"$2\": \([-0-9.e+]*\),\{0,1\}$/\1/p" "$1" | head -1; }
display_text() { sed -n "/^  \"display\": {/,/^  }/ s/^    \"$2\": \"\\(.*\\)\",\\{0,1\\}$/\\1/p" "$1" | head -1; }
json_escape() { sed 's/\\/\\\\/g; s/"/\\"/g' | tr -d '\n'; }

# One mode's medians and what showing the frame adds to it. The interop and host-copy runs alternate blocks of
# shown and only-rendered frames (--alternate-display): added_ms is the median frame time of the shown frames minus
# that of the hidden ones, within the one run, so the render's drift between runs stays out of it; fps and
# median_frame_ms are those of the shown frames. overhead_ms: that median minus the render alone's (--display none),
# a different run (its noise, about 0.1-0.2 ms on the dragon, included).
mode_json() {
  local m=$1
  if [ -n "${error[$m]:-}" ] || [ -z "${frame[$m]:-}" ]; then
    printf '{"error": "%s"}' "${error[$m]:-not run}"
    return
  fi
  awk -v f="${frame[$m]}" -v p="${present[$m]}" -v r="${render[$m]}" -v d="${display[$m]}" -v g="${gpu[$m]:-}" \
      -v a="${added[$m]:-}" -v h="${hidden[$m]:-}" -v hr="${hidden_render[$m]:-}" -v base="${frame[none]:-}" \
      -v name="${path[$m]}" -v detail="${detail[$m]}" 'BEGIN {
    printf "{\"path\": \"%s\", \"detail\": \"%s\", \"fps\": %.3f, \"median_frame_ms\": %.4f, ", name, detail, 1000 / f, f
    printf "\"median_render_ms\": %.4f, \"median_display_ms\": %.4f, \"median_present_ms\": %.4f", r, d, p
    if (g != "") printf ", \"median_gpu_display_ms\": %.4f", g
    if (h != "") printf ", \"median_frame_ms_not_shown\": %.4f, \"median_render_ms_not_shown\": %.4f", h, hr
    if (a != "") printf ", \"added_ms\": %.4f", a
    if (base != "") printf ", \"overhead_ms\": %.4f", f - base
    printf "}" }'
}

summary=$out/view-$tag.json
entries=()
runs=()
for backend in ${backends//,/ }; do
  name=${backend//:/-}
  declare -A frame=() present=() render=() display=() gpu=() added=() hidden=() hidden_render=() path=() detail=() \
             error=()
  modes="none interop host-copy"
  [[ ",$ablation," == *",$backend,"* ]] && modes="$modes copy-only gl-only"
  for mode in $modes; do
    stats=$out/view/$tag-$name-$mode.json
    log=$out/view/$tag-$name-$mode.log
    display=$mode ablate=
    case $mode in copy-only) display=interop ablate=copy ;; gl-only) display=interop ablate=gl ;; esac
    echo "== $backend, --display $display${ablate:+ PRISM_VIEW_ABLATE=$ablate} ($frames frames at ${width}x${height}, $(date -u +%H:%M:%S))"
    rm -f "$stats"
    # A time limit per run: a driver that hangs in one mode (a sync never signalled) must not take the session.
    PRISM_VIEW_ABLATE=$ablate timeout -k 10 "$run_limit" "$prism" view --headless --data-dir "$data" --scene "$scene" \
      --backend "$backend" --width "$width" --height "$height" --depth "$depth" --frames "$frames" --no-vsync \
      --display "$display" $([ "$mode" != none ] && echo --alternate-display "$alternate") --stats "$stats" >"$log" 2>&1
    status=$?
    [ $status -eq 124 ] || [ $status -eq 137 ] && echo "prism view: killed after ${run_limit} s" >>"$log"
    grep -E "^  (interop|display): |^  timing: " "$log" | sed 's/^/   /'
    if [ $status -ne 0 ] || [ ! -s "$stats" ]; then
      error[$mode]=$(tail -1 "$log" | json_escape)
      echo "   failed: ${error[$mode]}"
      continue
    fi
    error[$mode]=""
    frame[$mode]=$(field "$stats" median_frame_ms)
    present[$mode]=$(field "$stats" median_present_ms)
    render[$mode]=$(field "$stats" median_render_ms)
    display[$mode]=$(field "$stats" median_display_ms)
    gpu[$mode]=$(field "$stats" median_gpu_display_ms)   # empty when null (no GL work: --display none)
    if [ "$mode" != none ]; then
      frame[$mode]=$(alternating "$stats" median_frame_ms_shown)
      render[$mode]=$(alternating "$stats" median_render_ms_shown)
      hidden[$mode]=$(alternating "$stats" median_frame_ms_hidden)
      hidden_render[$mode]=$(alternating "$stats" median_render_ms_hidden)
      added[$mode]=$(alternating "$stats" added_ms)
    fi
    path[$mode]=$(display_text "$stats" name)
    detail[$mode]=$(display_text "$stats" detail)
    runs+=("\"$name-$mode\": $(cat "$stats")")
  done

  overhead=${added[interop]:-null}
  verdict=null
  [ "$overhead" != null ] && verdict=$(awk -v d="$overhead" -v t=$target_ms 'BEGIN { print (d <= t) ? "true" : "false" }')
  split=""
  if [[ "$modes" == *copy-only* ]]; then
    split=", \"interop_split\": {\"copy_only_added_ms\": ${added[copy-only]:-null}, \"gl_only_added_ms\": ${added[gl-only]:-null}, \"copy_only\": $(mode_json copy-only), \"gl_only\": $(mode_json gl-only)}"
  fi
  entries+=("\"$backend\": {\"render_only\": $(mode_json none), \"interop\": $(mode_json interop), \"host_copy\": $(mode_json host-copy), \"interop_overhead_ms\": $overhead, \"interop_meets_target\": $verdict$split}")
done

device=$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1)
driver=$(nvidia-smi --query-gpu=driver_version --format=csv,noheader 2>/dev/null | head -1)
commit=$(sed -n 's/^  "commit": "\([^"]*\)",\{0,1\}$/\1/p' "$out"/view/"$tag"-*.json 2>/dev/null | head -1)
{
  printf '{\n  "tool": "bench/view_gpu.sh",\n  "commit": "%s",\n  "date": "%s",\n' "$commit" "$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  printf '  "device": "%s",\n  "driver": "%s",\n  "gl": "%s",\n' "$device" "$driver" "$(printf '%s' "$gl" | json_escape)"
  printf '  "scene": "%s",\n  "width": %s,\n  "height": %s,\n  "depth": %s,\n  "frames": %s,\n' \
    "$scene" "$width" "$height" "$depth" "$frames"
  printf '  "target_interop_overhead_ms": %s,\n' "$target_ms"
  printf '  "alternate_block": %s,\n' "$alternate"
  printf '  "method": "prism view --headless (offscreen framebuffer, NVIDIA GL through an EGL device) --stats, medians over the frames after warm-up; GL runs asynchronously (no glFinish per frame). The interop and host-copy runs alternate blocks of alternate_block frames shown and frames only rendered (--alternate-display; the first frame of each block left out): added_ms = median frame time shown - median frame time not shown, within the one run. Shown frames copy the image into GL buffer in the frame (interop) or read it back (host copy): their render includes that. interop_overhead_ms: added_ms of interop; interop_meets_target: <= target. fps and median_frame_ms: the shown frames. overhead_ms: median_frame_ms minus that of --display none (the render alone, a different run: its noise included). median_gpu_display_ms: GL_TIME_ELAPSED of the display GL commands, for information. interop_split (PRISM_VIEW_ABLATION backends): added_ms with the shown frames only copying into the shared buffer (GL idle) and with GL only showing the shared buffer (no copy)",\n'
  printf '  "backends": {\n'
  for i in "${!entries[@]}"; do printf '    %s%s\n' "${entries[$i]}" "$([ $i -lt $((${#entries[@]} - 1)) ] && echo ,)"; done
  printf '  },\n  "runs": {\n'
  for i in "${!runs[@]}"; do printf '    %s%s\n' "${runs[$i]}" "$([ $i -lt $((${#runs[@]} - 1)) ] && echo ,)"; done
  printf '  }\n}\n'
} > "$summary"
echo "== wrote $summary"
