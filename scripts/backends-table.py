#!/usr/bin/env python3
"""The markdown table of a scripts/bench-backends.sh folder: one row per run, best of N beside
the median (a whole frame), the passes' best times, the SM clock nvidia-smi sampled during the
run, and the compute backend's memory and inexact pixels.

    scripts/backends-table.py OUT_DIR
"""
import json
import os
import sys


def frame_times(s):
    f = s.get("frame_ms")
    if isinstance(f, dict):
        return f.get("best"), f.get("median")
    passes = s.get("passes", [])
    best = sum(p.get("min_ms", p.get("gpu_ms", 0.0)) for p in passes)
    return best, s.get("gpu_ms_total")


def main(folder):
    names = sorted(n[:-5] for n in os.listdir(folder) if n.endswith(".json"))
    print("| run | cells | size | quantity | backend | best ms | median ms | passes (best ms) | Mcells/s (best) | backend bytes/cell, /pixel | inexact pixels | SM MHz (min/median/max) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for n in names:
        with open(os.path.join(folder, n + ".json")) as f:
            s = json.load(f)
        best, median = frame_times(s)
        passes = ", ".join("%s %.3g" % (p["name"], p.get("min_ms", p["gpu_ms"])) for p in s.get("passes", []))
        clock = s.get("sm_clock_mhz")
        clock = "%d/%d/%d" % (clock["min"], clock["median"], clock["max"]) if clock else "-"
        rate = s["cells"] / best / 1e3 if best else float("nan")
        mem = "%.0f, %.1f" % (s.get("backend_bytes_per_cell", 0), s.get("backend_bytes_per_pixel", 0))
        print("| %s | %d | %dx%d | %s | %s | %.3f | %.3f | %s | %.1f | %s | %s | %s |" % (
            n, s["cells"], s["width"], s["height"], s["quantity"], s.get("backend", "mesh"), best, median, passes, rate,
            mem, s.get("inexact_pixels", "-"), clock))


def clock_summary(folder):
    """nvidia-smi's SM clock over the whole run, while the GPU was more than 30 % busy."""
    path = os.path.join(folder, "clock.csv")
    if not os.path.exists(path):
        return
    busy = []
    for line in open(path):
        parts = [p.strip() for p in line.split(",")]
        try:
            mhz, util = float(parts[1]), float(parts[2])
        except (IndexError, ValueError):
            continue
        if util > 30:
            busy.append(mhz)
    busy.sort()
    if busy:
        print("\nSM clock while the GPU was over 30 %% busy: %d samples of 100 ms, min %d, median %d, max %d MHz" % (
            len(busy), busy[0], busy[len(busy) // 2], busy[-1]))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
    clock_summary(sys.argv[1])
