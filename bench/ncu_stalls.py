#!/usr/bin/env python3
"""Where a kernel's warps wait, from Nsight Compute's source page.

Reads `ncu --import R --page source --csv --print-source sass` output (one kernel launch) and prints the share of
the warp-state samples per stall reason and the SASS lines that hold the most samples. Used for the per-stage
profiles in bench/results/h200 (docs/kernels.md)."""
import argparse
import csv


def number(text):
    try:
        return float(text.replace(",", ""))
    except ValueError:
        return 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("source_csv")
    parser.add_argument("--top", type=int, default=12, help="SASS lines to list")
    args = parser.parse_args()
    header, rows, seen = None, [], set()
    with open(args.source_csv, newline="") as f:
        for row in csv.reader(f):
            if row and row[0] == "Address":
                header = row
            elif header and len(row) == len(header) and row[0] not in seen:  # the page repeats each line
                seen.add(row[0])
                rows.append(dict(zip(header, row)))
    if not rows:
        raise SystemExit(f"{args.source_csv}: no source lines (not an ncu --page source --csv export)")
    samples = "Warp Stall Sampling (All Samples)"
    total = sum(number(r[samples]) for r in rows)
    reasons = [h for h in header if h.startswith("stall_") and "Not Issued" not in h]
    print(f"{args.source_csv}: {len(rows)} SASS lines, {total:.0f} samples")
    for reason in sorted(reasons, key=lambda h: -sum(number(r[h]) for r in rows))[:6]:
        print(f"  {reason:26s} {100 * sum(number(r[reason]) for r in rows) / total:5.1f}%")
    print("  lines with the most samples:")
    for r in sorted(rows, key=lambda r: -number(r[samples]))[: args.top]:
        print(f"  {100 * number(r[samples]) / total:5.1f}%  {r['Source'].strip()[:70]}")


if __name__ == "__main__":
    main()
