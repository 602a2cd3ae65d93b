#!/usr/bin/env python3
"""Issue 19's ray sets side by side: reads the tinybvh-<mesh>-<size>-rN.json and prism-<mesh>-<size>-rN.json files
that bench/run_gpu.sh writes (PRISM_RAYS_SIZES) in one results folder and prints a Markdown table of Mrays/s,
tinybvh's range over its rounds against each API's, with Prism's ratio to tinybvh (lowest Prism over highest
tinybvh, highest over lowest), the lowest hit agreement with Embree, and issue 19's targets at 1920x1080.

    bench/ray_sets_table.py bench/results/h200/final-<commit>
"""
import argparse
import glob
import json
import os
import re
import sys

# Issue 19, item 2: Grays/s on 1920x1080 ray sets (1.25x its H200 tinybvh table).
TARGETS = {("dragon", "primary"): 6500, ("dragon", "diffuse"): 1270, ("bunny", "primary"): 12000,
           ("bunny", "diffuse"): 3190}
APIS = ["cuda", "opencl", "vulkan"]
NAME = re.compile(r"^(tinybvh|prism)-(.+)-(\d+x\d+)-r(\d+)\.json$")


def load(folder):
    """{(mesh, size): {"tinybvh": [json...], "prism": [json...]}}"""
    sets = {}
    for path in sorted(glob.glob(os.path.join(folder, "*.json"))):
        match = NAME.match(os.path.basename(path))
        if not match:
            continue
        who, mesh, size, _ = match.groups()
        with open(path) as f:
            sets.setdefault((mesh, size), {"tinybvh": [], "prism": []})[who].append(json.load(f))
    return sets


def span(values, digits=0):
    low, high = min(values), max(values)
    fmt = f"{{:.{digits}f}}"
    return fmt.format(low) if fmt.format(low) == fmt.format(high) else f"{fmt.format(low)}-{fmt.format(high)}"


def api_rates(runs, api, kind):
    rates, agreements = [], []
    for run in runs:
        for backend in run.get("backends", []):
            if backend.get("api") == api and kind in backend:
                rates.append(backend[kind]["mrays_per_s"])
                agreements.append(backend[kind]["agreement"])
    return rates, agreements


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    args = parser.parse_args()
    sets = load(args.folder)
    if not sets:
        sys.exit(f"ray_sets_table: {args.folder}: no tinybvh-*.json or prism-*.json ray sets")

    size_order = lambda size: int(size.split("x")[0]) * int(size.split("x")[1])
    print("| Mrays/s | tinybvh | CUDA | OpenCL | Vulkan | issue 19 (Prism's lowest, every API) |")
    print("|" + "---|" * (len(APIS) + 3))
    lowest_agreement = 1.0
    for (mesh, size) in sorted(sets, key=lambda k: (size_order(k[1]), k[0])):
        runs = sets[(mesh, size)]
        for kind in ("primary", "diffuse"):
            tiny = [r[kind]["mrays_per_s"] for r in runs["tinybvh"] if kind in r]
            lowest_agreement = min([lowest_agreement] + [r[kind]["agreement"] for r in runs["tinybvh"] if kind in r])
            cells = [span(tiny) if tiny else "-"]
            target = TARGETS.get((mesh, kind)) if size == "1920x1080" else None
            met = []
            for api in APIS:
                rates, agreements = api_rates(runs["prism"], api, kind)
                if not rates:
                    cells.append("-")
                    continue
                lowest_agreement = min([lowest_agreement] + agreements)
                cell = span(rates)
                if tiny:
                    cell += f" ({span([min(rates) / max(tiny), max(rates) / min(tiny)], 2)}x)"
                cells.append(cell)
                if target:
                    met.append(min(rates) >= target)
            goal = f">= {target}: {'met' if all(met) else 'not met'}" if target and met else ""
            print(f"| {mesh} {kind} {size} | " + " | ".join(cells) + f" | {goal} |")
    print(f"\nLowest hit agreement with Embree over these sets: {lowest_agreement * 100:.4f}%")


if __name__ == "__main__":
    main()
