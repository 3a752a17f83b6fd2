#!/usr/bin/python3
"""Lava from Python, as a notebook would use it: the same scene on both backends, compared
bit for bit, then one particle's trajectory plotted.

    PYTHONPATH=build/python docs/python_example.py docs/python-trajectory.png
Needs matplotlib (Debian: python3-matplotlib) for the plot.
"""
import sys

import numpy as np

import lava

# 1. The volcano preset on the GPU and on the CPU reference: the same bytes.
scene = "scenes/volcano.toml"
gpu = lava.simulate(2000, backend="gpu", scene=scene)
cpu = lava.simulate(2000, backend="cpu", scene=scene, threads=0)
alive = gpu[:, 6] >= 0
print(f"{alive.sum()} of {len(gpu)} slots alive; GPU and CPU bit-identical: "
      f"{gpu.tobytes() == cpu.tobytes()}")
print("validate:", {k: v for k, v in lava.validate(2000, every=500, scene=scene).items()
                    if k != "checkpoints"})

# 2. One particle step by step (the CPU backend's memory is viewed without a copy): a
# single vent particle launched at 45 degrees with three integrators.
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, ax = plt.subplots(figsize=(7, 4))
for integrator in ("explicit-euler", "semi-implicit-euler", "velocity-verlet"):
    sim = lava.Simulation("cpu", particles=1, rate=0, burst=1, spread=(0, 0, 0),
                          emitter_radius=0, velocity=(3, 3, 0), restitution=0.6,
                          integrator=integrator, dt=0.02)
    path = []
    for _ in range(120):
        sim.advance(1)
        path.append(sim.particles[0, :3].copy())  # px py pz of the one slot, in place
    path = np.array(path)
    ax.plot(path[:, 0], path[:, 1], label=integrator)
ax.set_xlabel("x (m)")
ax.set_ylabel("y (m)")
ax.set_title("One lava particle, h = 20 ms, bouncing off the ground")
ax.legend()
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "trajectory.png", dpi=100)
