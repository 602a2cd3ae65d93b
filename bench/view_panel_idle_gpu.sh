#!/usr/bin/env bash
# What the on-screen panel costs a frame, and what idling saves, on the GPU machine (docs/viewer.md, "Measuring the
# panel and idling"). Run from the repository root there after `source .gpu-runtime/env.sh`.
#   PRISM_BUILD (default build-gpu), PRISM_DATA (default .device-data/scenes), OUT (default bench/results/gpu),
#   PRISM_TAG (default: the GPU's name), PRISM_VIEW_BACKENDS (default cuda,vulkan:nvidia),
#   PRISM_VIEW_FRAMES (default 300), PRISM_IDLE_SECONDS (default 20), PRISM_VIEW_SCENE (default builtin:dragon),
#   PRISM_VIEW_SIZE (default 1920x1080)
# Writes view-panel-idle-<tag>.json: per backend, the scene at depth 8 shown through interop with and
# without the panel (--no-panel), and a still session against a continuously rendering one over the same seconds,
# with the GPU's utilisation and power sampled by nvidia-smi during each.
set -uo pipefail
build=${PRISM_BUILD:-build-gpu}
data=${PRISM_DATA:-.device-data/scenes}
out=${OUT:-bench/results/gpu}
frames=${PRISM_VIEW_FRAMES:-300}
idle_seconds=${PRISM_IDLE_SECONDS:-20}
backends=${PRISM_VIEW_BACKENDS:-cuda,vulkan:nvidia}
tag=${PRISM_TAG:-$(nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -1 | tr ' ' '-' | tr -cd 'A-Za-z0-9-')}
prism=$PWD/$build/apps/prism
runs=$out/view-panel-idle
mkdir -p "$runs"
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-$(mktemp -d)}; chmod 700 "$XDG_RUNTIME_DIR"
size=${PRISM_VIEW_SIZE:-1920x1080}
common=(view --headless --data-dir "$data" --scene "${PRISM_VIEW_SCENE:-builtin:dragon}" --width "${size%x*}"
        --height "${size#*x}" --depth 8 --no-vsync)

sample_gpu() {   # sample_gpu FILE: nvidia-smi in the background until killed
    nvidia-smi --query-gpu=utilization.gpu,power.draw --format=csv,noheader,nounits -lms 250 >"$1" 2>/dev/null &
    echo $!
}

IFS=',' read -ra list <<<"$backends"
for backend in "${list[@]}"; do
    name=${backend//:/-}
    for panel in panel no-panel; do
        extra=(); [ "$panel" = no-panel ] && extra=(--no-panel)
        echo "== $backend, interop, $panel"
        timeout 240 "$prism" "${common[@]}" --backend "$backend" --display interop --frames "$frames" "${extra[@]}" \
            --stats "$runs/$name-$panel.json" >"$runs/$name-$panel.log" 2>&1 || echo "  failed (log in $runs)"
    done
    for mode in idle busy; do
        extra=(); [ "$mode" = busy ] && extra=(--frames 1000000)
        echo "== $backend, $mode for $idle_seconds s"
        smi=$(sample_gpu "$runs/$name-$mode-smi.csv")
        timeout $((idle_seconds + 120)) "$prism" "${common[@]}" --backend "$backend" --seconds "$idle_seconds" \
            "${extra[@]}" --stats "$runs/$name-$mode.json" >"$runs/$name-$mode.log" 2>&1 || echo "  failed (log in $runs)"
        kill "$smi" 2>/dev/null; wait "$smi" 2>/dev/null
    done
done

python3 - "$runs" "$out/view-panel-idle-$tag.json" "$backends" <<'PY'
import json, os, statistics, sys
runs, target, backends = sys.argv[1], sys.argv[2], sys.argv[3].split(",")
def stats(path):
    try:
        with open(path) as f: return json.load(f)
    except (OSError, ValueError): return None
def smi(path):
    util, power = [], []
    try:
        for line in open(path):
            parts = [p.strip() for p in line.split(",")]
            if len(parts) == 2:
                try: util.append(float(parts[0])); power.append(float(parts[1]))
                except ValueError: pass
    except OSError: pass
    return {"samples": len(util), "mean_utilization_percent": statistics.fmean(util) if util else None,
            "mean_power_w": statistics.fmean(power) if power else None}
def timing(s, key):
    if not s: return None
    t = s.get("timing", s)
    return t.get(key) if isinstance(t, dict) else None
result = {"tool": "bench/view_panel_idle_gpu.sh", "backends": {}}
for backend in backends:
    name = backend.replace(":", "-")
    entry = {}
    for panel in ("panel", "no-panel"):
        entry[panel] = stats(os.path.join(runs, f"{name}-{panel}.json"))
    for mode in ("idle", "busy"):
        s = stats(os.path.join(runs, f"{name}-{mode}.json"))
        entry[mode] = {"stats": s, "gpu": smi(os.path.join(runs, f"{name}-{mode}-smi.csv")),
                       "frames_rendered": s.get("frames_rendered") if s else None}
    a, b = timing(entry["panel"], "median_frame_ms"), timing(entry["no-panel"], "median_frame_ms")
    entry["panel_cost_ms"] = (a - b) if a is not None and b is not None else None
    result["backends"][backend] = entry
    print(f"{backend}: frame with panel {a} ms, without {b} ms, panel costs {entry['panel_cost_ms']} ms; "
          f"idle rendered {entry['idle']['frames_rendered']} frames at {entry['idle']['gpu']['mean_utilization_percent']}% "
          f"/ {entry['idle']['gpu']['mean_power_w']} W, busy {entry['busy']['frames_rendered']} at "
          f"{entry['busy']['gpu']['mean_utilization_percent']}% / {entry['busy']['gpu']['mean_power_w']} W")
with open(target, "w") as f: json.dump(result, f, indent=2)
PY
