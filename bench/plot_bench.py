#!/usr/bin/env python3
"""Draws Prism's benchmark charts from the result files alone, so a chart can be redrawn anywhere from bench/results.

    bench/plot_bench.py RESULT.json [RESULT.json ...] [--baseline STATS.json ...] --out CHART.png

Each file becomes one row of the chart, by its contents:
  - `prism bench` results ("kind": "frames"): the seed table (median frame time per scene, one bar per backend)
    beside the ray throughput per API (primary, secondary and shadow Mrays/s per scene);
  - `prism bandwidth` results ("schema": "prism-bandwidth/1"): the bandwidth sweep, one panel per kind of copy,
    median GB/s against transfer size (log-log), one line per device;
  - `prism render --stats` files of split renders (they have "workers"; docs/scaling.md): all of them together make
    one row, the speedup of each over its --baseline (a one-device render of the same frame, or the same sequence:
    frame_ms or sequence_ms) against the ideal N (N = the run's GPU devices, distinct by rank and device; every
    worker when none is a GPU) with the 0.9 N target for a tiled frame and 0.95 N for a sequence, beside each run's
    tiles or frames per worker. --baseline is given once per kind (a frame's stats, a sequence's stats).
Each API keeps one colour in every panel (a second device of the same API gets a dashed line or hatched bars).
`prism bandwidth --plot F.png` runs this script. Needs matplotlib (Debian: python3-matplotlib, which
scripts/install-deps.sh installs). Exit status: 0 drawn, 1 a result file it cannot read, 2 bad arguments,
3 matplotlib missing."""
import argparse
import json
import math
import os
import sys

MATPLOTLIB_MISSING = 3

# One colour per API, the same in every chart.
API_COLORS = {
    "cuda": "#3a8c1c",
    "opencl": "#d62728",
    "vulkan": "#1f5fbf",
    "cpu": "#7f7f7f",
    "cpu-ref": "#2b2b2b",
    "embree": "#9467bd",
}
OTHER_COLORS = ["#ff7f0e", "#17becf", "#8c564b", "#e377c2", "#bcbd22"]
SECOND_DEVICE_STYLES = [("-", None), ("--", "//"), (":", ".."), ("-.", "xx")]

BANDWIDTH_KINDS = [
    ("h2d", "pageable", "host to device, pageable"),
    ("h2d", "pinned", "host to device, pinned"),
    ("d2h", "pageable", "device to host, pageable"),
    ("d2h", "pinned", "device to host, pinned"),
    ("d2d", "device", "device to device, copy command (bytes copied)"),
    ("kernel_copy", "device", "device to device, copy kernel (bytes copied)"),
]
RAY_TYPES = [("primary_mrays_per_s", "primary"), ("secondary_mrays_per_s", "secondary"),
             ("shadow_mrays_per_s", "shadow")]
FIGURE_WIDTH_INCHES = 16
DPI = 100


class ResultError(Exception):
    """A result file this script cannot draw; the message names the file."""


def api_of(backend):
    return backend.split(":", 1)[0]


class Palette:
    """Colour by API; the n-th distinct device of one API gets the n-th line style / hatch."""

    def __init__(self):
        self.devices = {}   # api -> list of device labels, in order of appearance
        self.extra = {}

    def color(self, api):
        if api in API_COLORS:
            return API_COLORS[api]
        if api not in self.extra:
            self.extra[api] = OTHER_COLORS[len(self.extra) % len(OTHER_COLORS)]
        return self.extra[api]

    def style(self, api, device):
        seen = self.devices.setdefault(api, [])
        if device not in seen:
            seen.append(device)
        return SECOND_DEVICE_STYLES[seen.index(device) % len(SECOND_DEVICE_STYLES)]


def read_result(path):
    try:
        with open(path) as f:
            data = json.load(f)
    except OSError as error:
        raise ResultError(f"{path}: cannot open ({error.strerror})")
    except json.JSONDecodeError as error:
        raise ResultError(f"{path}: invalid JSON: {error}")
    if not isinstance(data, dict):
        raise ResultError(f"{path}: expected a JSON object")
    if data.get("schema") == "prism-bandwidth/1":
        return "bandwidth", data
    if data.get("kind") == "frames":
        return "frames", data
    if "workers" in data and "ranks" in data:
        return "split", data
    if "frame_ms" in data and "backend" in data and "stages" in data:
        return "render", data
    raise ResultError(f"{path}: not a `prism bench` (\"kind\": \"frames\"), `prism bandwidth` "
                      "(\"schema\": \"prism-bandwidth/1\") or `prism render --stats` result")


def field(data, path, keys):
    """data[keys[0]][keys[1]]..., or a ResultError naming the file and the missing key."""
    value = data
    for key in keys:
        try:
            value = value[key]
        except (KeyError, IndexError, TypeError):
            raise ResultError(f"{path}: missing {'.'.join(str(k) for k in keys)}")
    return value


def size_label(size):
    for factor, suffix in ((1 << 30, "G"), (1 << 20, "M"), (1 << 10, "K")):
        if size >= factor and size % factor == 0:
            return f"{size // factor}{suffix}"
    return str(size)


def run_label(data, path):
    settings = field(data, path, ["settings"])
    label = f'{settings.get("width")}x{settings.get("height")}, depth {settings.get("max_depth")}'
    if settings.get("seed_setting"):
        label += " (the seed's setting)"
    return label


def frame_backends(data, path):
    """Backends in order of first appearance, with their API and device."""
    backends = {}
    for scene in field(data, path, ["scenes"]):
        for entry in field(scene, path, ["backends"]):
            if "frames" not in entry:   # a backend that failed on this scene has nothing to draw
                continue
            name = field(entry, path, ["backend"])
            backends.setdefault(name, (entry.get("api", api_of(name)), entry.get("device", "")))
    return backends


def backend_entry(scene, backend):
    return next((b for b in scene["backends"] if b["backend"] == backend and "frames" in b), None)


def bar_positions(group_count, index, count, width):
    return [g + (index - (count - 1) / 2) * width for g in range(group_count)]


def plain_log_axis(axis):
    """Log-scale tick labels as plain numbers (0.1, 6, 1000), minor ticks labelled when few decades are shown."""
    from matplotlib.ticker import LogFormatter

    class PlainLogFormatter(LogFormatter):
        # LogFormatter decides which ticks get a label; %g writes it (0.1, not 1e-01).
        def __call__(self, value, position=None):
            return f"{value:g}" if super().__call__(value, position) else ""

    axis.set_major_formatter(PlainLogFormatter(labelOnlyBase=False))
    axis.set_minor_formatter(PlainLogFormatter(labelOnlyBase=False, minor_thresholds=(2, 1.2)))


def draw_seed_table(ax, data, path, palette):
    scenes = field(data, path, ["scenes"])
    names = [field(s, path, ["scene"]).replace("builtin:", "") for s in scenes]
    backends = frame_backends(data, path)
    width = 0.8 / max(1, len(backends))
    for i, (backend, (api, device)) in enumerate(backends.items()):
        times = []
        for scene in scenes:
            entry = backend_entry(scene, backend)
            times.append(field(entry, path, ["frames", "frame_ms"]) if entry else float("nan"))
        _, hatch = palette.style(api, device)
        bars = ax.bar(bar_positions(len(scenes), i, len(backends), width), times, width, color=palette.color(api),
                      hatch=hatch, edgecolor="white", label=f"{backend}: {device}")
        ax.bar_label(bars, labels=[f"{t:.2f}" if math.isfinite(t) else "" for t in times], fontsize=7, rotation=90,
                     padding=2)
    ax.set_xticks(range(len(scenes)), names)
    ax.set_yscale("log")
    plain_log_axis(ax.yaxis)
    ax.set_ylabel("median frame time (ms, log scale)")
    ax.set_title(f"Seed table: frame time, {run_label(data, path)}")
    ax.margins(y=0.25)
    ax.legend(fontsize=8, loc="upper left")


def draw_ray_throughput(ax, data, path, palette):
    scenes = field(data, path, ["scenes"])
    groups = [(scene, key, f'{field(scene, path, ["scene"]).replace("builtin:", "")}\n{label}')
              for scene in scenes for key, label in RAY_TYPES]
    backends = frame_backends(data, path)
    width = 0.8 / max(1, len(backends))
    for i, (backend, (api, device)) in enumerate(backends.items()):
        rates = []
        for scene, key, _ in groups:
            entry = backend_entry(scene, backend)
            rates.append(entry["frames"].get(key, float("nan")) if entry else float("nan"))
        _, hatch = palette.style(api, device)
        ax.bar(bar_positions(len(groups), i, len(backends), width), rates, width, color=palette.color(api),
               hatch=hatch, edgecolor="white", label=backend)
    ax.set_xticks(range(len(groups)), [label for _, _, label in groups], fontsize=8)
    ax.set_yscale("log")
    plain_log_axis(ax.yaxis)
    ax.set_ylabel("ray queries (Mrays/s, log scale)")
    ax.set_title("Ray throughput per API (closest-hit primary and secondary, any-hit shadow)")
    ax.legend(fontsize=8, loc="upper right")


def draw_bandwidth(figure, cell, data, path, palette):
    grid = cell.subgridspec(2, 3, hspace=0.45, wspace=0.25)
    devices = field(data, path, ["devices"])
    sizes = field(data, path, ["sizes"])
    handles = {}
    for k, (direction, memory, title) in enumerate(BANDWIDTH_KINDS):
        ax = figure.add_subplot(grid[k // 3, k % 3])
        for device in devices:
            api = field(device, path, ["api"])
            name = field(device, path, ["device"])
            measurements = [m for m in field(device, path, ["measurements"])
                            if m.get("direction") == direction and m.get("memory") == memory]
            # Vulkan copies carry the queue they ran on; each queue is its own line (older files have none).
            for queue in dict.fromkeys(m.get("queue") for m in measurements):
                points = sorted((m["bytes"], (m.get("device_timer") or m["wall"])["median_gbps"])
                                for m in measurements if m.get("queue") == queue)
                label = f"{api}: {name}" + (f" [{queue} queue]" if queue else "")
                line_style, _ = palette.style(api, label)
                (line,) = ax.plot([p[0] for p in points], [p[1] for p in points], line_style, marker="o",
                                  markersize=3, color=palette.color(api), label=label)
                handles.setdefault(label, line)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        plain_log_axis(ax.yaxis)
        if sizes:
            ticks = sizes[:: max(1, len(sizes) // 5)]
            ax.set_xticks(ticks, [size_label(s) for s in ticks])
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("transfer size (bytes)", fontsize=8)
        ax.set_ylabel("GB/s (1e9 bytes/s)", fontsize=8)
        ax.grid(True, which="major", color="#dddddd")
        if not ax.lines:
            ax.text(0.5, 0.5, "no measurements", transform=ax.transAxes, ha="center")
    return handles


CPU_APIS = ("cpu", "cpu-ref", "embree")
SCALE_TARGETS = {"frame": 0.9, "sequence": 0.95}   # issue 20: of the ideal N, per kind of split


def split_kind(data, path):
    """"frame" (tiles of one frame) or "sequence" (whole frames), and the time the speedup compares."""
    if "sequence_ms" in data:
        return "sequence", field(data, path, ["sequence_ms"])
    return "frame", field(data, path, ["frame_ms"])


def what_is_rendered(data, path):
    return tuple(field(data, path, [key]) for key in ("scene", "width", "height", "max_depth"))


def gpu_devices(workers, path):
    """Distinct (rank, device) pairs of GPU workers; a bare `cuda` is its API's device 0."""
    devices = set()
    for w in workers:
        backend = field(w, path, ["backend"])
        api = api_of(backend)
        if api not in CPU_APIS:
            devices.add((field(w, path, ["rank"]), backend if ":" in backend else f"{api}:0"))
    return devices


def scale_runs(results, baselines):
    """One entry per split render: its name, kind, N, speedup and workers, checked against its baseline."""
    runs = []
    for data, path in results:
        kind, ms = split_kind(data, path)
        if kind not in baselines:
            raise ResultError(f"{path}: a split {kind}: give a one-device {kind} with --baseline to compare it with")
        base, base_path = baselines[kind]
        _, base_ms = split_kind(base, base_path)
        if what_is_rendered(base, base_path) != what_is_rendered(data, path):
            raise ResultError(f"{path}: renders {what_is_rendered(data, path)}, its baseline {base_path} "
                              f"{what_is_rendered(base, base_path)}")
        workers = field(data, path, ["workers"])
        if not workers or ms <= 0:
            raise ResultError(f"{path}: no workers or no time recorded")
        n = len(gpu_devices(workers, path)) or len(workers)
        item = "frames" if kind == "sequence" else "tiles"
        runs.append({"name": os.path.basename(path).removesuffix(".json"), "kind": kind, "n": n,
                     "speedup": base_ms / ms, "ms": ms, "workers": workers, "item": item, "data": data,
                     "path": path})
    return runs


def run_caption(run):
    data = run["data"]
    path = run["path"]
    how = f'tiles of {data.get("tile_size", "?")}' if run["kind"] == "frame" else \
        f'{field(data, path, ["frames", "last"]) - field(data, path, ["frames", "first"]) + 1} frames'
    ranks = data.get("ranks", 1)
    return f'{run["name"]}\n{how}, {len(run["workers"])} workers' + (f", {ranks} ranks" if ranks > 1 else "")


def run_color(run, palette):
    apis = [api_of(w["backend"]) for w in run["workers"]]
    return palette.color(next((a for a in apis if a not in CPU_APIS), apis[0]))


def draw_speedup(ax, runs, baselines, palette):
    for x, run in enumerate(runs):
        target = SCALE_TARGETS[run["kind"]] * run["n"]
        ax.bar(x, run["speedup"], 0.6, color=run_color(run, palette), edgecolor="white")
        ax.hlines(run["n"], x - 0.4, x + 0.4, colors="black", linewidths=2, label="ideal N" if x == 0 else None)
        ax.hlines(target, x - 0.4, x + 0.4, colors="black", linestyles="dashed", linewidths=1.2,
                  label="target: 0.9 N (frame), 0.95 N (sequence)" if x == 0 else None)
        mark = "met" if run["speedup"] >= target else "missed"
        ax.annotate(f'{run["speedup"]:.2f}x\nN={run["n"]}, {mark}', (x, max(run["speedup"], run["n"])),
                    xytext=(0, 3), textcoords="offset points", ha="center", va="bottom", fontsize=8)
    ax.set_xticks(range(len(runs)), [run_caption(r) for r in runs], fontsize=8)
    ax.set_ylabel("speedup (baseline time / run time)")
    ax.set_ylim(0, max(max(r["speedup"], r["n"]) for r in runs) * 1.3)
    parts = []
    for kind, (data, path) in sorted(baselines.items()):
        _, ms = split_kind(data, path)
        parts.append(f'{os.path.basename(path)}: {ms:.1f} ms per {kind}')
    ax.set_title("Split renders: speedup over one device (baseline " + "; ".join(parts) + ")")
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(True, axis="y", color="#dddddd")


def draw_shares(ax, runs, palette):
    handles = {}
    for x, run in enumerate(runs):
        total = sum(w.get(run["item"], 0) for w in run["workers"])
        bottom = 0.0
        for w in run["workers"]:
            share = 100.0 * w.get(run["item"], 0) / total if total else 0.0
            api = api_of(w["backend"])
            label = f'{api}: {w["device"]}'
            _, hatch = palette.style(api, w["device"])
            bar = ax.bar(x, share, 0.6, bottom=bottom, color=palette.color(api), hatch=hatch, edgecolor="white")
            handles.setdefault(label, bar)
            if share >= 6:
                who = w["backend"] + (f' (rank {w["rank"]})' if run["data"].get("ranks", 1) > 1 else "")
                ax.text(x, bottom + share / 2, f'{who}\n{w.get(run["item"], 0)} {run["item"]}, {share:.0f}%',
                        ha="center", va="center", fontsize=7, color="white")
            bottom += share
    ax.set_xticks(range(len(runs)), [run_caption(r) for r in runs], fontsize=8)
    ax.set_ylim(0, 100)
    ax.set_ylabel("share of the tiles / frames (%)")
    ax.set_title("Work taken by each worker")
    ax.legend(list(handles.values()), list(handles.keys()), fontsize=8, loc="upper center",
              bbox_to_anchor=(0.5, -0.2), ncol=min(3, len(handles)))


def title_of(data):
    parts = [f"commit {data.get('commit', '?')}", str(data.get("date", "?"))]
    return ", ".join(parts)


def draw(results, out, baselines=None):
    # The split renders make one row together, where the first of them is.
    split = [(data, path) for kind, data, path in results if kind == "split"]
    runs = scale_runs(split, baselines or {}) if split else []
    rows_in = []
    for kind, data, path in results:
        if kind == "render":
            raise ResultError(f"{path}: a one-device render's stats: give it with --baseline")
        if kind != "split":
            rows_in.append((kind, data, path))
        elif not any(k == "split" for k, _, _ in rows_in):
            rows_in.append(("split", None, None))
    results = rows_in
    try:
        import matplotlib
    except ImportError:
        print(f"plot_bench.py: matplotlib is missing for {sys.executable}: install it with "
              "`sudo apt-get install python3-matplotlib` (scripts/install-deps.sh does) and run this script "
              "with /usr/bin/python3", file=sys.stderr)
        return MATPLOTLIB_MISSING
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    heights = [9.0 if kind == "bandwidth" else 11.0 if kind == "split" else 5.5 for kind, _, _ in results]
    figure = plt.figure(figsize=(FIGURE_WIDTH_INCHES, sum(heights) + 0.8))
    rows = figure.add_gridspec(len(results), 1, height_ratios=heights, hspace=0.35)
    palette = Palette()
    for row, (kind, data, path) in enumerate(results):
        if kind == "split":
            cells = rows[row].subgridspec(2, 1, hspace=0.35)
            draw_speedup(figure.add_subplot(cells[0]), runs, baselines, palette)
            draw_shares(figure.add_subplot(cells[1]), runs, palette)
        elif kind == "frames":
            cells = rows[row].subgridspec(1, 2, wspace=0.2, width_ratios=[1, 1.4])
            draw_seed_table(figure.add_subplot(cells[0]), data, path, palette)
            ax = figure.add_subplot(cells[1])
            draw_ray_throughput(ax, data, path, palette)
            ax.annotate(title_of(data), (1, 1.08), xycoords="axes fraction", ha="right", fontsize=8)
        else:
            handles = draw_bandwidth(figure, rows[row], data, path, palette)
            anchor = figure.axes[-6]
            anchor.annotate(f"Bandwidth sweep: median of {data.get('repeats', '?')} copies, device timer where "
                            f"the API has one ({title_of(data)})", (0, 1.25), xycoords="axes fraction", fontsize=11)
            if handles:
                figure.axes[-2].legend(list(handles.values()), list(handles.keys()), loc="upper center",
                                       bbox_to_anchor=(0.5, -0.28), ncol=min(2, len(handles)), fontsize=9)
    # Written beside the target and renamed, so a failed run leaves no partial PNG.
    partial = f"{out}.partial"
    try:
        figure.savefig(partial, format="png", dpi=DPI, bbox_inches="tight")
        os.replace(partial, out)
    except OSError as error:
        if os.path.exists(partial):
            os.remove(partial)
        raise ResultError(f"{out}: cannot write ({error.strerror})")
    finally:
        plt.close(figure)
    print(f"wrote {out}")
    return 0


def main():
    parser = argparse.ArgumentParser(description="Draw Prism benchmark charts from result JSON files.")
    parser.add_argument("results", nargs="+", help="result files of `prism bench`, `prism bandwidth` or split "
                        "`prism render --stats`")
    parser.add_argument("--baseline", action="append", default=[],
                        help="`prism render --stats` of one device that split renders are compared with: one frame, "
                             "one sequence (give it once per kind)")
    parser.add_argument("--out", required=True, help="the PNG to write")
    args = parser.parse_args()
    if not args.out.lower().endswith(".png"):
        parser.error(f"--out: expected a .png file name, got '{args.out}'")
    try:
        results = [(*read_result(path), path) for path in args.results]
        baselines = {}
        for path in args.baseline:
            kind, data = read_result(path)
            if kind not in ("render", "split"):
                raise ResultError(f"{path}: --baseline: not a `prism render --stats` file")
            split, _ = split_kind(data, path)
            if split in baselines:
                raise ResultError(f"{path}: --baseline: a second {split} baseline beside {baselines[split][1]}")
            baselines[split] = (data, path)
        return draw(results, args.out, baselines)
    except ResultError as error:
        print(f"plot_bench.py: error: {error}", file=sys.stderr)
        return 1
    except (KeyError, TypeError, ValueError) as error:   # a result file of another layout than documented
        print(f"plot_bench.py: error: {', '.join(args.results)}: unexpected result layout ({error!r})",
              file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
