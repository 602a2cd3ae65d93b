#!/usr/bin/env python3
"""Draws the seed table (thesis Tables 2/3 redone) from `prism bench` JSON files: frame time per scene and backend,
and primary/secondary/shadow Mrays/s. Usage: bench/plot_seed_table.py RESULT.json [...] --out chart.png
Needs matplotlib (pip install matplotlib); it reads only the JSON, so charts can be redrawn anywhere."""
import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(paths):
    runs = []
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        settings = data["settings"]
        label = f'{settings["width"]}x{settings["height"]} depth {settings["max_depth"]}'
        runs.append((label, data))
    return runs


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("results", nargs="+")
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    runs = load(args.results)
    fig, axes = plt.subplots(len(runs), 2, figsize=(13, 4.2 * len(runs)), squeeze=False)
    for row, (label, data) in enumerate(runs):
        scenes = [s["scene"].replace("builtin:", "") for s in data["scenes"]]
        backends = [b["backend"] for b in data["scenes"][0]["backends"]]
        width = 0.8 / len(backends)
        ax_time, ax_rays = axes[row]
        for i, backend in enumerate(backends):
            times, primary = [], []
            for scene in data["scenes"]:
                entry = next(b for b in scene["backends"] if b["backend"] == backend)
                times.append(entry["frames"]["frame_ms"])
                primary.append(entry["frames"]["primary_mrays_per_s"])
            xs = [x + (i - (len(backends) - 1) / 2) * width for x in range(len(scenes))]
            bars = ax_time.bar(xs, times, width, label=backend)
            ax_time.bar_label(bars, labels=[f"{t:.2f}" for t in times], fontsize=7, rotation=90, padding=2)
            ax_rays.bar(xs, primary, width, label=backend)
        ax_time.set_xticks(range(len(scenes)), scenes)
        ax_time.set_yscale("log")
        ax_time.set_ylabel("frame time (ms, log)")
        ax_time.set_title(f"Frame time, {label} ({data['commit']})")
        ax_time.legend(fontsize=8)
        ax_rays.set_xticks(range(len(scenes)), scenes)
        ax_rays.set_ylabel("primary rays (Mrays/s)")
        ax_rays.set_title("Primary-ray intersect throughput")
        ax_rays.legend(fontsize=8)
    device = data["scenes"][0]["backends"][0]["device"]
    fig.suptitle(f"Prism seed table on {device} ({data['date']})")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
