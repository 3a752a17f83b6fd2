"""`import lava` against the `lava` program's own .npy files, on lavapipe with the
validation layer (ctest sets PYTHONPATH, LAVA_EXE, VK_DRIVER_FILES and LAVA_VALIDATION)."""
import os
import subprocess

import numpy as np
import pytest

import lava

LAVA = os.environ["LAVA_EXE"]
SCENES = os.path.join(os.path.dirname(__file__), "..", "..", "scenes")


def program(tmp_path, *args):
    out = str(tmp_path / "state.npy")
    subprocess.run([LAVA, "simulate", *args, "--out", out], check=True, capture_output=True)
    return np.load(out)


def test_simulate_matches_the_programs_npy_on_every_backend(tmp_path):
    for backend in ("gpu", "cpu", "cpu-simd"):
        state = lava.simulate(1500, backend=backend, emitter_radius=0.2, rate=3000)
        assert state.dtype == np.float32 and state.shape == (5000, 7)
        expected = program(tmp_path, "--steps", "1500", "--backend", backend,
                           "--emitter-radius", "0.2", "--rate", "3000")
        assert np.array_equal(state, expected)


def test_gpu_and_cpu_are_bit_identical_with_every_module(tmp_path):
    scene = os.path.join(SCENES, "volcano.toml")
    gpu = lava.simulate(800, scene=scene, integrator="velocity-verlet")
    cpu = lava.simulate(800, backend="cpu", scene=scene, integrator="velocity-verlet", threads=2)
    simd = lava.simulate(800, backend="cpu-simd", scene=scene, integrator="velocity-verlet",
                         threads=2)
    assert gpu.tobytes() == cpu.tobytes() == simd.tobytes()
    assert np.array_equal(gpu, program(tmp_path, "--steps", "800", "--scene", scene,
                                       "--integrator", "velocity-verlet"))


def test_vectors_names_and_sequences_are_accepted():
    state = lava.simulate(200, backend="cpu", emitter=(0.0, 1.0, 0.0), velocity=[1, 2, 3],
                          spread=np.zeros(3), shape="box", particles=300, rate=50000)
    alive = state[state[:, 6] >= 0]
    assert len(alive) == 300
    assert np.allclose(alive[:, 3], 1.0)  # no spread: every vx is exactly 1 (no drag, wind)


def test_validate_reports_checkpoints_and_no_divergence():
    report = lava.validate(1200, every=400, shape="sphere", emitter_radius=0.3)
    assert report["passed"] is True
    assert report["first_divergent_step"] is None
    assert report["first_difference"] is None
    assert [c["step"] for c in report["checkpoints"]] == [400, 800, 1200]
    assert all(c["equal"] == c["particles"] == 5000 for c in report["checkpoints"])
    assert all(c["max_ulp"] == 0 for c in report["checkpoints"])


def test_simulation_advances_and_the_cpu_view_needs_no_copy():
    sim = lava.Simulation(backend="cpu", rate=2000)
    sim.advance(300)
    view = sim.particles
    assert view.shape == (5000, 8) and not view.flags["OWNDATA"] and not view.flags["WRITEABLE"]
    before = view[0].copy()
    sim.advance(10)
    assert sim.step == 310
    assert not np.array_equal(view[0], before)  # the same memory, moved on
    assert np.array_equal(sim.state(), lava.simulate(310, backend="cpu", rate=2000))
    gpu = lava.Simulation(backend="gpu", rate=2000)
    gpu.advance(310)
    assert np.array_equal(gpu.state(), sim.state())
    assert np.array_equal(gpu.particles, np.array(view))
    assert "rate = 2000" in gpu.scene_toml


def test_bad_values_raise_value_error_naming_the_parameter():
    for kwargs, name in [({"emitter_radius": -1}, "emitter_radius"), ({"restitution": 2}, "restitution"),
                         ({"shape": "torus"}, "shape"), ({"wind": (1, 2)}, "wind"),
                         ({"lava_temperature": 3}, "lava_temperature"), ({"mass": True}, "mass")]:
        with pytest.raises(ValueError, match=name):
            lava.simulate(10, backend="cpu", **kwargs)
    with pytest.raises(ValueError, match="backend"):
        lava.simulate(10, backend="tpu")
    with pytest.raises(ValueError, match="scene"):
        lava.simulate(10, scene="/nonexistent.toml")


def test_a_scene_file_with_program_options_serves_python_too(tmp_path):
    scene = tmp_path / "shared.toml"
    scene.write_text("particles = 123\nsteps = 20\nframes = 2\n")
    assert lava.simulate(20, backend="cpu", scene=str(scene)).shape == (123, 7)


def test_checkpoints_read_in_numpy_without_lava(tmp_path):
    # The checkpoint is an .npz numpy opens; its state is simulate's .npy, its raw
    # particles the same floats, its clock and scene readable.
    ck = str(tmp_path / "run.npz")
    scene = os.path.join(SCENES, "volcano.toml")
    subprocess.run([LAVA, "simulate", "--scene", scene, "--steps", "700", "--checkpoint", ck],
                   check=True, capture_output=True)
    z = np.load(ck)
    assert set(z.files) == {"format", "scene", "step", "clock", "particles", "state", "hash",
                            "checksum"}
    assert z["format"][0] == 1 and int(z["step"]) == 700
    assert np.array_equal(z["state"], program(tmp_path, "--scene", scene, "--steps", "700"))
    raw = z["particles"]
    assert raw.shape == (36000, 8)
    assert np.array_equal(raw[:, [0, 1, 2, 4, 5, 6, 3]], z["state"])
    assert list(z["clock"].dtype.names) == ["accumulator", "serial", "head"]
    assert z["clock"]["serial"].tolist() == [2800, 700, 700]
    assert "[[collider]]" in bytes(z["scene"]).decode()


def test_a_checkpoint_of_another_format_is_refused_by_name(tmp_path):
    # Rewritten by numpy (its own ZIP writer) with format 9: Lava reads the archive and says
    # which format it is.
    ck, other = str(tmp_path / "run.npz"), str(tmp_path / "other.npz")
    subprocess.run([LAVA, "simulate", "--steps", "10", "--checkpoint", ck], check=True,
                   capture_output=True)
    arrays = dict(np.load(ck))
    arrays["format"] = np.array([9], dtype="<u4")
    np.savez(other, **arrays)
    r = subprocess.run([LAVA, "simulate", "--resume", other, "--steps", "1"],
                       capture_output=True, text=True)
    assert r.returncode == 2
    assert "checkpoint format 9; this Lava reads format 1" in r.stderr, r.stderr
    # Unchanged but rewritten by numpy: still a checkpoint Lava resumes.
    arrays["format"] = np.array([1], dtype="<u4")
    np.savez(other, **arrays)
    r = subprocess.run([LAVA, "simulate", "--resume", other, "--steps", "1"],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_a_flow_adds_the_temperature_column_and_its_checkpoint_arrays(tmp_path):
    # scenes/eruption-explicit.toml: sparks (emitter 0, 12000 slots), then the flow (16384),
    # on the explicit flow, which the GPU steps with its own shader.
    scene = os.path.join(SCENES, "eruption-explicit.toml")
    state = lava.simulate(300, backend="cpu", scene=scene)
    assert state.shape == (28384, 8)
    assert np.array_equal(state, program(tmp_path, "--backend", "cpu", "--scene", scene,
                                         "--steps", "300"))
    sparks, rock = state[:12000], state[12000:]
    assert (sparks[:, 7] == 0).all()
    born = rock[:, 6] >= 0
    assert born.any() and ((rock[born, 7] > 1300) & (rock[born, 7] <= 1400)).all()
    assert (rock[~born, 7] == 0).all()
    ck = str(tmp_path / "flow.npz")
    subprocess.run([LAVA, "simulate", "--backend", "cpu", "--scene", scene, "--steps", "300",
                    "--checkpoint", ck], check=True, capture_output=True)
    z = np.load(ck)
    assert {"temperature", "crust"} <= set(z.files)
    assert np.array_equal(z["temperature"][12000:][born], rock[born, 7])
    assert z["crust"].dtype == np.uint8 and z["crust"].shape == (28384,)
    # The GPU (the default) gives the same bytes, temperatures included.
    assert lava.Simulation(scene).backend == "gpu"
    assert np.array_equal(lava.simulate(300, scene=scene), state)


def accepted_keywords():
    """The scene's keywords and device, threads, as the unknown-parameter error lists them."""
    with pytest.raises(ValueError) as error:
        lava.simulate(1, backend="cpu", no_such_keyword=1)
    listed = str(error.value).split("(accepted: ")[1].rstrip(")")
    return listed.split(", ")


class Opaque:
    """A value of a type no keyword takes."""


def raises_naming(name, call):
    with pytest.raises((TypeError, ValueError)) as error:
        call()
    assert str(error.value).startswith(name + ":"), (name, str(error.value))


def test_every_keyword_of_the_wrong_type_raises_an_error_naming_it(tmp_path):
    keys = accepted_keywords()
    assert {"particles", "velocity", "integrator", "device", "threads"} <= set(keys)
    for name in keys:
        raises_naming(name, lambda: lava.simulate(1, backend="cpu", **{name: Opaque()}))
        raises_naming(name, lambda: lava.Simulation(backend="cpu", **{name: Opaque()}))
        raises_naming(name, lambda: lava.render(frames=1, size=(8, 8), **{name: Opaque()}))
    for name in ("fps", "warmup", "renderer", "look", "exposure", "bloom", "bloom_threshold",
                 "frames", "size", "scene"):
        raises_naming(name, lambda: lava.render(**{"frames": 1, "size": (8, 8), name: Opaque()}))
    for name in ("steps", "backend", "scene", "every", "series"):
        given = {"steps": 1, "backend": "cpu", "series": str(tmp_path / "s"), "every": 1}
        raises_naming(name, lambda: lava.simulate(**{**given, name: Opaque()}))
    for name in ("steps", "every", "scene", "tolerance_ulp"):
        raises_naming(name, lambda: lava.validate(**{"steps": 2, name: Opaque()}))
    raises_naming("scene", lambda: lava.Simulation(scene=Opaque()))
    raises_naming("backend", lambda: lava.Simulation(backend=Opaque()))
    sim = lava.Simulation(backend="cpu")
    raises_naming("steps", lambda: sim.advance(Opaque()))
    raises_naming("steps", lambda: sim.advance("10"))
    raises_naming("path", lambda: sim.checkpoint(Opaque()))
    raises_naming("particles", lambda: sim.set_state(Opaque()))
    raises_naming("particles", lambda: sim.set_state("x"))
    raises_naming("folder", lambda: sim.write_series(Opaque(), 1, 1))
    raises_naming("steps", lambda: sim.write_series(str(tmp_path / "w"), Opaque(), 1))
    raises_naming("every", lambda: sim.write_series(str(tmp_path / "w"), 1, Opaque()))
    raises_naming("path", lambda: lava.Simulation.resume(Opaque()))
    raises_naming("backend", lambda: lava.Simulation.resume(str(tmp_path / "x.npz"), Opaque()))
    raises_naming("path", lambda: lava.Scene(Opaque()))
    # A wrong type is both a TypeError and a ValueError (bad input was a ValueError before).
    with pytest.raises(lava.ArgumentTypeError):
        lava.simulate("10")
    assert issubclass(lava.ArgumentTypeError, TypeError)
    assert issubclass(lava.ArgumentTypeError, ValueError)


def test_render_takes_the_command_lines_size(tmp_path):
    text = lava.render(frames=1, size="32x18", warmup=0.1)[0]
    assert text.shape == (18, 32, 3)
    assert np.array_equal(text, lava.render(frames=1, size=(32, 18), warmup=0.1)[0])
    for bad in ("32x", "x18", "32*18", "0x18"):
        raises_naming("size", lambda: lava.render(frames=1, size=bad))


def test_presets_load_by_name_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert {"volcano", "eruption", "crater"} <= set(lava.presets())
    volcano = lava.Scene("volcano")
    assert volcano == lava.Scene(os.path.join(SCENES, "volcano.toml"))
    assert lava.Scene("volcano.toml") == volcano
    assert np.array_equal(lava.simulate(20, backend="cpu", scene="volcano"),
                          lava.simulate(20, backend="cpu", scene=volcano))
    assert lava.Scene("flow") == lava.Scene(os.path.join(SCENES, "modules", "flow.toml"))
    with pytest.raises(ValueError, match="no preset.*volcano"):
        lava.Scene("volcanoes")


def test_a_series_from_python_is_the_programs(tmp_path):
    flow = os.path.join(SCENES, "modules", "flow.toml")
    subprocess.run([LAVA, "simulate", "--scene", flow, "--steps", "120", "--series",
                    str(tmp_path / "cli"), "--every", "40"], check=True, capture_output=True)
    lava.simulate(120, scene="flow", series=tmp_path / "py", every=40)
    sim = lava.Simulation("flow", backend="cpu")
    sim.write_series(str(tmp_path / "sim"), 50, 40)  # samples at 0 and 40
    sim.write_series(str(tmp_path / "sim"), 70, 40)  # continued: 80 and 120
    cli = sorted(os.listdir(tmp_path / "cli"))
    assert cli == ["step_%012d.vtp" % k for k in (0, 40, 80, 120)]
    for other in ("py", "sim"):
        assert sorted(os.listdir(tmp_path / other)) == cli
        for name in cli:
            assert (tmp_path / other / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
        assert ((tmp_path / (other + ".pvd")).read_text().replace(other + "/", "") ==
                (tmp_path / "cli.pvd").read_text().replace("cli/", ""))
    with pytest.raises(ValueError, match="every"):
        lava.simulate(10, series=str(tmp_path / "x"))
    with pytest.raises(ValueError, match="every"):
        lava.simulate(10, every=5)
    with pytest.raises(ValueError, match="series"):  # run.pvd goes beside a named folder
        lava.Simulation("flow", backend="cpu").write_series(".", 10, 5)
