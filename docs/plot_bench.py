#!/usr/bin/python3
"""Throughput vs particle count from `lava bench --json` runs (medians across runs).

Usage: docs/plot_bench.py OUT.png RUN.json [RUN.json ...]
Needs matplotlib (Debian: python3-matplotlib); it is a docs tool, not a build dependency.
"""
import json
import statistics
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(out, runs):
    updates = defaultdict(list)  # (backend, particles) -> [updates/s]
    roofline = defaultdict(list)  # (backend, particles) -> [copy GB/s / bytes per update]
    compute = defaultdict(list)  # (backend, particles) -> [compute ceiling updates/s]
    device = None
    for path in runs:
        with open(path) as f:
            data = json.load(f)
        device = data["device"]
        for r in data["results"]:
            key = (r["backend"], r["particles"])
            updates[key].append(r["updates_per_second"])
            roofline[key].append(r["copy_gbps"] * 1e9 / r["bytes_per_update"])
            if r.get("compute_updates_per_second", 0) > 0:
                compute[key].append(r["compute_updates_per_second"])

    fig, ax = plt.subplots(figsize=(10, 5), dpi=110)
    styles = {"gpu": ("#d62d0a", "o"), "cpu": ("#4a4a4a", "s"), "cpu-mt": ("#8a8a8a", "^"),
              "cpu-simd": ("#1f5fbf", "D"), "cpu-simd-mt": ("#5aa0f0", "v")}
    memory_roofs = {"gpu", "cpu", "cpu-mt"}  # the CPU rows share memcpy's: drawn once each
    for backend, (color, marker) in styles.items():
        sizes = sorted(n for b, n in updates if b == backend)
        if not sizes:
            continue
        med = [statistics.median(updates[(backend, n)]) / 1e6 for n in sizes]
        ax.plot(sizes, med, marker=marker, color=color, label=f"{backend} (end to end)")
        if backend in memory_roofs:
            roof = [statistics.median(roofline[(backend, n)]) / 1e6 for n in sizes]
            ax.plot(sizes, roof, linestyle="--", color=color, alpha=0.6,
                    label=f"{backend} memory roofline (copy bandwidth / 64 B)")
        if all((backend, n) in compute for n in sizes):
            ceil = [statistics.median(compute[(backend, n)]) / 1e6 for n in sizes]
            ax.plot(sizes, ceil, linestyle=":", color=color, alpha=0.8,
                    label=f"{backend} compute ceiling (its steps alone)")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("particles")
    ax.set_ylabel("million particle-steps per second (median of runs)")
    ax.set_title(f"lava bench, {len(runs)} runs, {device}", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(out)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2:])
