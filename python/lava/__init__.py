"""Lava: a Vulkan compute-shader particle engine whose GPU and CPU results agree bit for bit.

    import lava
    state = lava.simulate(3000, backend="gpu", emitter_radius=0.2)   # float32 (particles, 7)
    report = lava.validate(3000, every=500, integrator="velocity-verlet")
    scene = lava.Scene("volcano", rate=4000)                          # a preset, or a file
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

import os as _os

from ._lava import (ArgumentTypeError, Error, ResourceError, Scene,  # noqa: F401
                    Simulation, VulkanError, __version__, render, simulate, validate)

__all__ = ["ArgumentTypeError", "Error", "ResourceError", "Scene", "Simulation", "VulkanError",
           "__version__", "presets", "render", "simulate", "validate"]


def presets():
    """The names of the scenes the package ships (scenes/*.toml of the repository): each
    loads with lava.Scene(name) or scene=name, from any folder."""
    folder = _os.path.join(_os.path.dirname(__file__), "scenes")
    return sorted(f[:-5] for f in _os.listdir(folder) if f.endswith(".toml"))
