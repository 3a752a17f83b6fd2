"""The Pythonic surface: scenes, simulations that save and resume, frames as arrays, errors,
Ctrl-C. Run against whichever `lava` is imported: the build tree's (ctest's Python.Pytest)
or the installed package (Python.InstalledPackage)."""
import os
import signal
import struct
import subprocess
import threading
import time
import zlib

import numpy as np
import pytest

import lava

LAVA = os.environ["LAVA_EXE"]
SCENES = os.path.join(os.path.dirname(__file__), "..", "..", "scenes")


def read_png(path):
    """An 8-bit RGBA PNG as stb writes it, as uint8 (height, width, 4)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color = struct.unpack(">IIBB", body[:10])
            assert (depth, color) == (8, 6)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride, bpp = width * 4, 4
    out = np.zeros((height, stride), np.uint8)
    prev = np.zeros(stride, np.int32)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1)
        cur = line.astype(np.int32)
        if kind == 1 or kind == 3 or kind == 4:
            for x in range(stride):
                left = cur[x - bpp] if x >= bpp else 0
                up, upleft = prev[x], prev[x - bpp] if x >= bpp else 0
                if kind == 1:
                    predictor = left
                elif kind == 3:
                    predictor = (left + up) // 2
                else:
                    p = left + up - upleft
                    pa, pb, pc = abs(p - left), abs(p - up), abs(p - upleft)
                    predictor = left if pa <= pb and pa <= pc else up if pb <= pc else upleft
                cur[x] = (cur[x] + predictor) & 255
        elif kind == 2:
            cur = (cur + prev) & 255
        out[y] = cur
        prev = cur
    return out.reshape(height, width, 4)


def test_render_returns_the_programs_png_frames_pixel_for_pixel(tmp_path):
    for renderer in ("lines", "splat"):
        frames = lava.render(frames=2, size=(96, 64), warmup=0.5, renderer=renderer, rate=4000)
        assert len(frames) == 2
        assert all(f.dtype == np.uint8 and f.shape == (64, 96, 3) for f in frames)
        out = tmp_path / renderer
        subprocess.run([LAVA, "render", "--frames", "2", "--size", "96x64", "--warmup", "0.5",
                        "--renderer", renderer, "--rate", "4000", "--out", str(out)],
                       check=True, capture_output=True)
        for i, frame in enumerate(frames):
            png = read_png(out / ("frame_%05u.png" % i))
            assert np.array_equal(frame, png[:, :, :3]), "%s frame %d" % (renderer, i)
        assert frames[0].max() > 100  # lava, not a black image


def test_render_checks_its_keywords():
    with pytest.raises(ValueError, match="size"):
        lava.render(size=(0, 10))
    with pytest.raises(ValueError, match="look"):
        lava.render(look="neon")
    with pytest.raises(ValueError, match="fps"):
        lava.render(fps=0)
    with pytest.raises(ValueError, match="emitter_radius"):
        lava.render(emitter_radius=-1)
    with pytest.raises(ValueError, match="fps"):
        lava.render(fps="fast")
    with pytest.raises(ValueError, match="renderer"):
        lava.render(renderer=3)


def test_a_scene_loads_edits_prints_and_saves(tmp_path):
    scene = lava.Scene(os.path.join(SCENES, "volcano.toml"), rate=4000)
    assert scene.emitters >= 2 and scene.colliders >= 1
    assert "rate = 4000" in str(scene)
    scene.set("radius", 0.5, table="collider", index=0)
    with pytest.raises(ValueError, match="radius"):
        scene.set("radius", -1, table="collider", index=0)
    path = tmp_path / "edited.toml"
    scene.save(str(path))
    again = lava.Scene(str(path))
    assert again == scene and lava.Scene.from_toml(scene.to_toml()) == scene
    assert "particles" in repr(scene)
    with pytest.raises(ValueError, match="rate"):
        lava.Scene(rate="fast")
    assert np.array_equal(lava.simulate(300, backend="cpu", scene=scene),
                          lava.simulate(300, backend="cpu", scene=str(path)))
    # Top-level keys as attributes; every table in to_dict().
    assert scene.dt == 0.001 and scene.line_scale == scene.to_dict()["line-scale"]
    scene.gravity = 3.7  # Mars
    scene.rate = 2500    # emitter 0's
    assert scene.gravity == 3.7 and scene.to_dict()["emitter"][0]["rate"] == 2500
    assert scene.to_dict()["collider"][0]["radius"] == 0.5
    with pytest.raises(ValueError, match="gravity"):
        scene.gravity = "strong"
    with pytest.raises(AttributeError, match="gravty"):
        scene.gravty = 1
    with pytest.raises(AttributeError):
        scene.emitter


def test_a_checkpoint_resumes_bit_for_bit_on_another_backend(tmp_path):
    scene = lava.Scene(os.path.join(SCENES, "volcano.toml"))
    run = lava.Simulation(scene, backend="gpu")
    run.advance(700)
    run.checkpoint(str(tmp_path / "run.npz"))
    run.advance(500)
    with pytest.raises(ValueError, match="rate"):
        lava.Simulation.resume(str(tmp_path / "run.npz"), rate=5)
    resumed = lava.Simulation.resume(str(tmp_path / "run.npz"), backend="cpu")
    assert resumed.step == 700 and resumed.scene == scene
    resumed.advance(500)
    assert resumed.state().tobytes() == run.state().tobytes()


def test_set_state_replaces_the_slots():
    sim = lava.Simulation(backend="cpu", rate=3000)
    sim.advance(200)
    slots = np.array(sim.particles)
    other = lava.Simulation(backend="gpu", rate=3000)
    other.advance(200)
    other.set_state(slots)
    assert np.array_equal(other.particles, slots)
    with pytest.raises(ValueError, match="particles"):
        other.set_state(slots[:, :7])


def test_errors_are_value_errors_or_lava_errors():
    assert issubclass(lava.ResourceError, lava.Error) and issubclass(lava.VulkanError, lava.Error)
    assert issubclass(lava.Error, RuntimeError)
    with pytest.raises(ValueError, match="backend"):
        lava.Simulation(backend="fpga")
    with pytest.raises(ValueError, match="not-there.npz"):
        lava.Simulation.resume("not-there.npz")


def test_long_calls_release_the_gil_and_ctrl_c_interrupts_them():
    sim = lava.Simulation(backend="cpu", particles=200000, rate=200000)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        sim.advance(10_000_000)  # hours, unless interrupted
    done.set()
    counter.join()
    timer.join()
    assert time.monotonic() - started < 30
    assert len(ticks) > 20  # Python ran beside the steps
    assert 0 < sim.step < 10_000_000 and sim.step % 1024 == 0  # stopped at a whole batch
