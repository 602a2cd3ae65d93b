#!/usr/bin/env python3
"""Issue 19's ray sets side by side: reads the tinybvh-<mesh>-<size>-rN.json and prism-<mesh>-<size>-rN.json files
that bench/run_gpu.sh writes (PRISM_RAYS_SIZES) in one results folder and prints a Markdown table of Mrays/s,
tinybvh's range over its rounds against each API's, with Prism's ratio to tinybvh (lowest Prism over highest
tinybvh, highest over lowest), the lowest hit agreement with Embree, and issue 19's targets at 1920x1080.

    bench/ray_sets_table.py bench/results/h200/final-<commit>

With --builds, an A/B of builds instead (bench/ab_builds.sh's LABEL-<mesh>-rN.json): each build's rounds in turn,
per mesh, ray kind and API, and the change of the mean from the first build to each other one.

    bench/ray_sets_table.py FOLDER --builds main probe
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


def ab_table(folder, labels):
    runs = {}  # (label, mesh) -> [json, ...] in round order
    for label in labels:
        pattern = re.compile(rf"^{re.escape(label)}-(.+)-r(\d+)\.json$")
        for path in glob.glob(os.path.join(folder, f"{glob.escape(label)}-*-r*.json")):
            match = pattern.match(os.path.basename(path))
            if not match:
                continue
            with open(path) as f:
                result = json.load(f)
            # Only ray sets: ab_builds.sh's frames (prism bench) sit beside them.
            if any("primary" in backend for backend in result.get("backends", [])):
                runs.setdefault((label, match.group(1)), []).append((int(match.group(2)), result))
    meshes = sorted({mesh for (_, mesh) in runs})
    if not meshes:
        sys.exit(f"ray_sets_table: {folder}: no ray sets of builds {', '.join(labels)}")
    print(f"Mrays/s, rounds in order ({' -> '.join(labels)}); in brackets the mean's change from {labels[0]}\n")
    print("| | CUDA | OpenCL | Vulkan |")
    print("|---|---|---|---|")
    lowest_agreement = 1.0
    for mesh in meshes:
        for kind in ("primary", "diffuse"):
            cells = []
            for api in APIS:
                groups, means = [], []
                for label in labels:
                    ordered = [run for _, run in sorted(runs.get((label, mesh), []), key=lambda r: r[0])]
                    rates, agreements = api_rates(ordered, api, kind)
                    lowest_agreement = min([lowest_agreement] + agreements)
                    groups.append(", ".join(f"{rate:.0f}" if rate >= 100 else f"{rate:.2f}" for rate in rates) or "-")
                    means.append(sum(rates) / len(rates) if rates else None)
                changes = [f"{(m / means[0] - 1) * 100:+.1f}%" for m in means[1:] if m and means[0]]
                cells.append(" -> ".join(groups) + (f" ({', '.join(changes)})" if changes else ""))
            print(f"| {mesh} {kind} | " + " | ".join(cells) + " |")
    print(f"\nLowest hit agreement with Embree over these sets: {lowest_agreement * 100:.4f}%")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder")
    parser.add_argument("--builds", nargs="+", metavar="LABEL", help="an A/B of bench/ab_builds.sh's builds")
    args = parser.parse_args()
    if args.builds:
        ab_table(args.folder, args.builds)
        return
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
