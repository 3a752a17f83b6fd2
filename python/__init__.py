"""Lava: a Vulkan compute-shader particle engine whose GPU and CPU results agree bit for bit.

    import lava
    state = lava.simulate(3000, backend="gpu", emitter_radius=0.2)   # float32 (particles, 7)
    report = lava.validate(3000, every=500, integrator="velocity-verlet")
    sim = lava.Simulation("cpu", scene="scenes/volcano.toml"); sim.advance(100)

The columns are those of `lava simulate --out FILE.npy`: px py pz vx vy vz age.
"""
try:
    import numpy  # noqa: F401
except ImportError:  # another python3 of the same version on PATH: use Debian's numpy
    import sys

    sys.path.append("/usr/lib/python3/dist-packages")
    import numpy  # noqa: F401

from ._lava import (ResourceError, Simulation, VulkanError, __version__, simulate,  # noqa: F401
                    validate)
