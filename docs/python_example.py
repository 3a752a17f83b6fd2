#!/usr/bin/python3
"""Lava from Python, as a notebook would use it: the same scene on both backends, compared
bit for bit, a frame rendered into an array, one particle's trajectory plotted, and the
eruption's molten rock coloured by its temperature.

    .venv/bin/python docs/python_example.py docs   # writes python-render.png,
                                                   # python-trajectory.png, python-flow.png
Needs matplotlib (Debian: python3-matplotlib, which third_party/install-deps.sh installs) for
the pictures. Runs from any folder: the scenes are the package's presets, by name.
"""
import os
import sys

import numpy as np

import lava

folder = sys.argv[1] if len(sys.argv) > 1 else "."

# 1. The volcano preset on the GPU and on the CPU reference: the same bytes.
scene = lava.Scene("volcano")  # a preset the package ships, by name
gpu = lava.simulate(2000, backend="gpu", scene=scene)
cpu = lava.simulate(2000, backend="cpu", scene=scene, threads=0)
alive = gpu[:, 6] >= 0
print(f"{alive.sum()} of {len(gpu)} slots alive; GPU and CPU bit-identical: "
      f"{gpu.tobytes() == cpu.tobytes()}")
print("validate:", {k: v for k, v in lava.validate(2000, every=500, scene=scene).items()
                    if k != "checkpoints"})

# 2. A frame of it, as `lava render` would write it, straight into an array.
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

frame = lava.render(scene, frames=1, size=(640, 360))[0]  # uint8 (360, 640, 3)
plt.imsave(os.path.join(folder, "python-render.png"), frame)

# 3. One particle step by step (the CPU backend's memory is viewed without a copy): a
# single vent particle launched at 45 degrees with three integrators.
fig, ax = plt.subplots(figsize=(7, 4))
for integrator in ("explicit-euler", "semi-implicit-euler", "velocity-verlet"):
    sim = lava.Simulation(backend="cpu", particles=1, rate=0, burst=1, spread=(0, 0, 0),
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
fig.savefig(os.path.join(folder, "python-trajectory.png"), dpi=100)

# 4. The eruption's flow: the 8th column is the temperature. 8 s of it (480 steps of 1/60 s)
# on the CPU's SIMD kernels, which step the implicit flow as the reference does.
state = lava.simulate(480, scene="eruption", backend="cpu-simd", threads=0)
rock = state[12000:]                                # emitter 1's slots: the flow
rock = rock[rock[:, 6] >= 0]                        # alive
fig, ax = plt.subplots(figsize=(6, 5))
dots = ax.scatter(rock[:, 0], rock[:, 2], c=rock[:, 7], s=2, cmap="inferno", vmin=1000,
                  vmax=1400)
fig.colorbar(dots, label="temperature (K)")
ax.set_aspect("equal")
ax.set_xlabel("x (m)")
ax.set_ylabel("z (m)")
ax.set_title(f"eruption.toml at 8 s: {len(rock)} flow particles")
fig.tight_layout()
fig.savefig(os.path.join(folder, "python-flow.png"), dpi=100)
