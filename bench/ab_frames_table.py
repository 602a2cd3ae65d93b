#!/usr/bin/env python3
"""Markdown table of an A/B of builds from their `prism bench --json` files (the README tables under
bench/results/h200/ab-*): per scene, backend and build, the frame and the intersect, shadow and shade stages in ms,
one column entry per round, and the image hash (two if the rounds differ). With --host: the frame and where its
host time went instead of the stages (enqueue, device wait, read-back), for changes to launching and waiting.

Usage: ab_frames_table.py FOLDER LABEL=PATTERN... where PATTERN names a build's files with {round} for its round
number, e.g. `base=base-1080p-r{round}.json`; --rounds N (default 2)."""
import argparse
import json
import os


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("folder")
    parser.add_argument("builds", nargs="+", help="LABEL=PATTERN, PATTERN with {round}")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--host", action="store_true", help="host time columns instead of stage columns")
    args = parser.parse_args()
    rows = {}
    labels = []
    for build in args.builds:
        label, pattern = build.split("=", 1)
        labels.append(label)
        for r in range(1, args.rounds + 1):
            with open(os.path.join(args.folder, pattern.format(round=r))) as f:
                result = json.load(f)
            for scene in result["scenes"]:
                for backend in scene["backends"]:
                    frames = backend["frames"]
                    parts = frames["host_ms"] if args.host else frames["stage_ms"]
                    keys = ("enqueue", "device_wait", "readback") if args.host else ("intersect", "shadow", "shade")
                    rows.setdefault((scene["scene"], backend["backend"]), {}).setdefault(label, []).append(
                        (frames["frame_ms"], *(parts[k] for k in keys), frames["image_hash"]))
    columns = "enqueue | device wait | read-back" if args.host else "intersect | shadow | shade"
    print(f"| scene | API | build | frame ms | {columns} | image_hash |")
    print("|---|---|---|---|---|---|---|---|")
    for (scene, backend), by_label in rows.items():
        for label in labels:
            runs = by_label.get(label, [])
            if not runs:
                continue
            cell = lambda i: " / ".join("%.2f" % run[i] for run in runs)
            hashes = sorted({str(run[4]) for run in runs})
            print(f"| {scene} | {backend} | {label} | {cell(0)} | {cell(1)} | {cell(2)} | {cell(3)} | "
                  f"{' / '.join(hashes)} |")


if __name__ == "__main__":
    main()
