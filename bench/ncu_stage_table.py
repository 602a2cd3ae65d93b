#!/usr/bin/env python3
"""Per-stage table of an Nsight Compute profile of one frame (docs/kernels.md, "Stages under Nsight Compute").

Reads `ncu --import R --page raw --csv` of a frame profiled with -k regex:'prism_cuda_(intersect|shade|shadow|miss)'
(each depth from its intersect launch on, in frame order) and the frame's `prism render --stats` JSON (rays per depth), and prints
per launch: time, registers, achieved occupancy, L1 and L2 hit rates, and the bytes DRAM and L2 moved per ray."""
import argparse
import csv
import json

METRICS = {
    "time_us": "gpu__time_duration.sum",
    "registers": "launch__registers_per_thread",
    "occupancy_pct": "sm__warps_active.avg.pct_of_peak_sustained_active",
    "l1_hit_pct": "l1tex__t_sector_hit_rate.pct",
    "l2_hit_pct": "lts__t_sector_hit_rate.pct",
    "dram_read_gb": "dram__bytes_read.sum",
    "dram_write_gb": "dram__bytes_write.sum",
    "l2_to_sm_tbps": "derived__lts__lts2xbar_bytes.sum.per_second",
}
SCALE = {"Gbyte": 1e9, "Mbyte": 1e6, "Kbyte": 1e3, "byte": 1.0, "Tbyte": 1e12, "Gbyte/s": 1e9, "Tbyte/s": 1e12,
         "usecond": 1e-6, "msecond": 1e-3, "nsecond": 1e-9, "us": 1e-6, "ms": 1e-3, "ns": 1e-9}


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("raw_csv")
    parser.add_argument("stats_json")
    args = parser.parse_args()
    rows = list(csv.reader(open(args.raw_csv, newline="")))
    header, units, launches = rows[0], rows[1], rows[2:]
    column = {name: header.index(metric) for name, metric in METRICS.items()}
    stats = json.load(open(args.stats_json))

    def value(launch, name):
        i = column[name]
        v = float(launch[i].replace(",", ""))
        return v * SCALE.get(units[i], 1.0) if name in ("time_us", "dram_read_gb", "dram_write_gb", "l2_to_sm_tbps") \
            else v

    print("depth stage      rays     time_ms regs occ% L1hit% L2hit% DRAM_B/ray L2->SM_B/ray")
    depth = -1
    for launch in launches:
        stage = launch[header.index("Kernel Name")].split("(")[0].replace("prism_cuda_", "")
        # Each depth starts with its closest-hit launch (intersect, or intersect_mesh for a scene of one mesh);
        # a frame may launch stages the profile's filter took in besides the four (occlude: shadow rays).
        if stage.startswith("intersect"):
            depth += 1
        shadow = stage == "shadow" or stage.startswith("occlude")
        rays = stats["shadow_rays_per_depth" if shadow else "rays_per_depth"][depth]
        seconds = value(launch, "time_us")
        dram = value(launch, "dram_read_gb") + value(launch, "dram_write_gb")
        l2 = value(launch, "l2_to_sm_tbps") * seconds
        print(f"{depth:5d} {stage:9s} {rays:8d} {seconds * 1e3:9.3f} {value(launch, 'registers'):4.0f} "
              f"{value(launch, 'occupancy_pct'):4.1f} {value(launch, 'l1_hit_pct'):6.1f} "
              f"{value(launch, 'l2_hit_pct'):6.1f} {dram / rays:10.1f} {l2 / rays:12.1f}")


if __name__ == "__main__":
    main()
