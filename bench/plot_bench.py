#!/usr/bin/env python3
"""Draws Prism's benchmark charts from the result files alone, so a chart can be redrawn anywhere from bench/results.

    bench/plot_bench.py RESULT.json [RESULT.json ...] --out CHART.png

Each file becomes one row of the chart, by its contents:
  - `prism bench` results ("kind": "frames"): the seed table (median frame time per scene, one bar per backend)
    beside the ray throughput per API (primary, secondary and shadow Mrays/s per scene);
  - `prism bandwidth` results ("schema": "prism-bandwidth/1"): the bandwidth sweep, one panel per kind of copy,
    median GB/s against transfer size (log-log), one line per device.
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
    raise ResultError(f"{path}: not a `prism bench` (\"kind\": \"frames\") or `prism bandwidth` "
                      "(\"schema\": \"prism-bandwidth/1\") result")


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
            points = sorted((m["bytes"], (m.get("device_timer") or m["wall"])["median_gbps"])
                            for m in field(device, path, ["measurements"])
                            if m.get("direction") == direction and m.get("memory") == memory)
            if not points:
                continue
            line_style, _ = palette.style(api, name)
            (line,) = ax.plot([p[0] for p in points], [p[1] for p in points], line_style, marker="o", markersize=3,
                              color=palette.color(api), label=f"{api}: {name}")
            handles.setdefault(f"{api}: {name}", line)
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


def title_of(data):
    parts = [f"commit {data.get('commit', '?')}", str(data.get("date", "?"))]
    return ", ".join(parts)


def draw(results, out):
    try:
        import matplotlib
    except ImportError:
        print(f"plot_bench.py: matplotlib is missing for {sys.executable}: install it with "
              "`sudo apt-get install python3-matplotlib` (scripts/install-deps.sh does) and run this script "
              "with /usr/bin/python3", file=sys.stderr)
        return MATPLOTLIB_MISSING
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    heights = [9.0 if kind == "bandwidth" else 5.5 for kind, _, _ in results]
    figure = plt.figure(figsize=(FIGURE_WIDTH_INCHES, sum(heights) + 0.8))
    rows = figure.add_gridspec(len(results), 1, height_ratios=heights, hspace=0.35)
    palette = Palette()
    for row, (kind, data, path) in enumerate(results):
        if kind == "frames":
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
    parser.add_argument("results", nargs="+", help="result files of `prism bench` or `prism bandwidth`")
    parser.add_argument("--out", required=True, help="the PNG to write")
    args = parser.parse_args()
    if not args.out.lower().endswith(".png"):
        parser.error(f"--out: expected a .png file name, got '{args.out}'")
    try:
        results = [(*read_result(path), path) for path in args.results]
        return draw(results, args.out)
    except ResultError as error:
        print(f"plot_bench.py: error: {error}", file=sys.stderr)
        return 1
    except (KeyError, TypeError, ValueError) as error:   # a result file of another layout than documented
        print(f"plot_bench.py: error: {', '.join(args.results)}: unexpected result layout ({error!r})",
              file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
