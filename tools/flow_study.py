#!/usr/bin/env python3
"""The flow against a published solution: a fixed volume of flow released on the ground at
constant viscosity, with no cooling, spreads as an axisymmetric viscous gravity current.
Huppert (J. Fluid Mech. 121, 1982) gives its front's radius for times long after the
release:

    r_N(t) = 0.894 (g V^3 t / (3 nu))^(1/8)

This runs the pool on the CPU reference (`import lava`) and measures its front two ways,
about the pool's centre: from the bulk, sqrt(7/3 <r^2>) (for Huppert's profile
h ~ (1 - (r/r_N)^2)^(1/3) that is r_N exactly), and the radius within which 99% of the
particles lie. It writes the table, a summary and the plot of docs/flow.md.

Usage: tools/flow_study.py [--particles N] [--seconds T] [--viscosity NU] [--out DIR]
(PYTHONPATH must reach the built module: build/python.)
"""
import argparse
import math
import os
import sys
import time

import numpy as np

import lava

HUPPERT = (1024.0 / (81.0 * math.pi ** 3)) ** 0.125  # 0.894: the similarity constant


def pool_scene(n, viscosity, radius):
    side = 0.5 * (n * (0.5 * radius) ** 3) ** (1.0 / 3.0)  # particles spaced radius/2
    return lava.Scene.from_toml(f"""
[[emitter]]
particles = {n}
rate = 0
burst = {n}
shape = "box"
size = [{side}, {side}, {side}]
position = [0, {side + 0.005}, 0]
velocity = [0, 0, 0]
spread = [0, 0, 0]
flow = true

[flow]
radius = {radius}
viscosity = {viscosity}
viscosity-solidus = {viscosity}
cooling-air = 0
cooling-ground = 0
""", "flow-study")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--particles", type=int, default=8000)
    parser.add_argument("--seconds", type=float, default=30.0)
    parser.add_argument("--viscosity", type=float, default=0.05)
    parser.add_argument("--radius", type=float, default=0.06)
    parser.add_argument("--every", type=float, default=0.25, help="seconds between samples")
    parser.add_argument("--out", default="docs")
    a = parser.parse_args()

    scene = pool_scene(a.particles, a.viscosity, a.radius)
    flow = scene.to_dict()["flow"]
    mass = scene.to_dict()["emitter"][0]["mass"]
    volume = a.particles * mass / flow["density"]
    g, nu = 9.81, a.viscosity
    sim = lava.Simulation(scene, backend="cpu", threads=os.cpu_count() or 1)
    steps = int(round(a.every / 0.001))
    rows = []
    began = time.time()
    for k in range(1, int(round(a.seconds / a.every)) + 1):
        sim.advance(steps)
        x, y, z = sim.state()[:, 0], sim.state()[:, 1], sim.state()[:, 2]
        r = np.hypot(x - x.mean(), z - z.mean())
        t = k * a.every
        front = float(np.sqrt(7.0 / 3.0 * np.mean(r * r)))
        edge = float(np.quantile(r, 0.99))
        theory = HUPPERT * (g * volume ** 3 * t / (3.0 * nu)) ** 0.125
        rows.append((t, front, edge, theory, float(y.max())))
        print(f"t = {t:6.2f} s  front {front:.4f} m (99%: {edge:.4f})  Huppert {theory:.4f} m "
              f"({front / theory:.3f})  top {y.max():.4f} m", flush=True)
    wall = time.time() - began

    os.makedirs(os.path.join(a.out, "data"), exist_ok=True)
    table = os.path.join(a.out, "data", "flow-spreading.csv")
    with open(table, "w") as f:
        f.write("t_s,front_m,edge99_m,huppert_m,top_m\n")
        for row in rows:
            f.write(",".join(f"{v:.6g}" for v in row) + "\n")
    # The exponent over the second half of the run (log-log slope) and the constant it
    # implies against Huppert's 0.894.
    late = [row for row in rows if row[0] >= a.seconds / 2]
    tt = np.log([row[0] for row in late])
    rr = np.log([row[1] for row in late])
    slope = float(np.polyfit(tt, rr, 1)[0])
    ratio = float(np.median([row[1] / row[3] for row in late]))
    print(f"{a.particles} particles, V = {volume:.5f} m^3, nu = {nu} m^2/s, {a.seconds} s "
          f"in {wall:.0f} s: exponent {slope:.3f} (theory 0.125), front / Huppert "
          f"{ratio:.3f} over the second half")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is missing: no plot", file=sys.stderr)
        return
    t = [row[0] for row in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.loglog(t, [row[1] for row in rows], "o", ms=3,
              label=f"Lava, {a.particles} particles: √(7/3 ⟨r²⟩)")
    ax.loglog(t, [row[2] for row in rows], "x", ms=3, label="Lava: 99% of the particles within")
    ax.loglog(t, [row[3] for row in rows], "-", label="Huppert (1982): 0.894 (g V³ t / 3ν)^(1/8)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("front radius (m)")
    ax.set_title(f"A released pool, ν = {nu} m²/s, V = {volume * 1e3:.2f} L: exponent "
                 f"{slope:.3f} (1/8)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "flow-spreading.png"), dpi=100)


if __name__ == "__main__":
    main()
