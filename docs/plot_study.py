#!/usr/bin/python3
"""The integrator study as two plots: position error against h before the first ground
contact (log-log), and E(t)/E(0) over time with an elastic ground, one line per integrator.

Usage: build/lava study --csv study.csv --energy-csv energy.csv
       docs/plot_study.py OUT.png study.csv energy.csv [DT]    (DT: the step of the energy
       panel, default 0.003)
Needs matplotlib (Debian: python3-matplotlib); a docs tool, not a build dependency.
"""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(out, table, series, dt=0.003):
    errors = defaultdict(list)
    with open(table) as f:
        for row in csv.DictReader(f):
            errors[row["integrator"]].append((float(row["dt"]), float(row["max_position_error"])))
    energy = defaultdict(list)
    with open(series) as f:
        for row in csv.DictReader(f):
            if abs(float(row["dt"]) - dt) < 1e-12:
                energy[row["integrator"]].append((float(row["t"]), float(row["energy_ratio"])))
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, points in errors.items():
        points.sort()
        left.loglog([p[0] for p in points], [p[1] for p in points], "o-", label=name)
    left.set_xlabel("step h (s)")
    left.set_ylabel("max |x - x*| before the first bounce (m)")
    left.set_title("Error against the parabola (float32)")
    left.grid(True, which="both", alpha=0.3)
    left.legend()
    for name, points in energy.items():
        right.plot([p[0] for p in points], [p[1] for p in points], label=name)
    right.axhline(1.0, color="gray", lw=0.8)
    right.set_xlabel("t (s)")
    right.set_ylabel("E(t) / E(0)")
    right.set_title(f"Energy, elastic ground, h = {dt} s")
    right.grid(True, alpha=0.3)
    right.legend()
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], sys.argv[3], *(float(a) for a in sys.argv[4:5]))
