"""Lava: a Vulkan compute-shader particle engine whose GPU and CPU results agree bit for bit.

    import lava
    state = lava.simulate(3000, backend="gpu", emitter_radius=0.2)   # float32 (particles, 7)
    report = lava.validate(3000, every=500, integrator="velocity-verlet")
    scene = lava.Scene("scenes/volcano.toml", rate=4000)
    sim = lava.Simulation(scene, backend="cpu"); sim.advance(100); sim.checkpoint("run.npz")
    frames = lava.render(scene, frames=3, size=(640, 360))          # uint8 (360, 640, 3) each

The columns are those of `lava simulate --out FILE.npy`: px py pz vx vy vz age. Bad input
raises ValueError naming the parameter; Vulkan and resource errors raise lava.Error (a
RuntimeError). docs/python.md has the rest.
"""
try:
    import numpy  # noqa: F401
except ImportError:  # another python3 of the same version on PATH: use Debian's numpy
    import sys

    sys.path.append("/usr/lib/python3/dist-packages")
    import numpy  # noqa: F401

from ._lava import (Error, ResourceError, Scene, Simulation, VulkanError,  # noqa: F401
                    __version__, render, simulate, validate)

__all__ = ["Error", "ResourceError", "Scene", "Simulation", "VulkanError", "__version__",
           "render", "simulate", "validate"]
