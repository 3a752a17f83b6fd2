#!/usr/bin/env python3
"""`lava simulate --series DIR --every K` read back with VTK's own XML reader (SPEC §4):
every sample's points and arrays equal, bit for bit, the same run's checkpoint at that step;
the collection's times are step × dt; a run stopped by SIGINT leaves only whole samples and a
collection naming exactly them, and `--resume` continues it to the bytes of a straight run;
`lava render --series` (and `render --resume`) writes the samples simulate writes.

Usage: series_test.py LAVA SCENES SCRATCH"""
import os
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

lava, scenes, scratch = sys.argv[1:4]
shutil.rmtree(scratch, ignore_errors=True)
os.makedirs(scratch)
scene = os.path.join(scenes, "modules", "flow.toml")
capacities = [3000, 300, 150]  # the scene's emitters' rings, in order
dt = 0.001
common = ["simulate", "--scene", scene, "--dt", str(dt)]
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what)


def lava_run(*args, resume=False):
    done = subprocess.run([lava, *(["simulate"] if resume else common), *args],
                          capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit("FAIL: lava %s exited %d: %s" % (" ".join(args), done.returncode, done.stderr))
    return done.stdout


def read_sample(path):
    """The sample's arrays as numpy, and its field data; any VTK error fails the test."""
    errors = []
    reader = vtkXMLPolyDataReader()
    reader.AddObserver("ErrorEvent", lambda obj, event: errors.append(path))
    reader.AddObserver("WarningEvent", lambda obj, event: errors.append(path))
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    check(not errors, "VTK could not read %s" % path)
    n = data.GetNumberOfPoints()
    arrays = {"Points": vtk_to_numpy(data.GetPoints().GetData()) if n else np.zeros((0, 3), "f4")}
    point_data = data.GetPointData()
    for i in range(point_data.GetNumberOfArrays()):
        arrays[point_data.GetArrayName(i)] = vtk_to_numpy(point_data.GetArray(i))
    fields = {}
    for i in range(data.GetFieldData().GetNumberOfArrays()):
        array = data.GetFieldData().GetArray(i)
        fields[array.GetName()] = array.GetValue(0)
    check(data.GetNumberOfVerts() == n, "%s: one vertex a point" % path)
    return n, arrays, fields


def same_bits(a, b):
    a, b = np.ascontiguousarray(a), np.ascontiguousarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and a.tobytes() == b.tobytes()


def collection(pvd):
    """[(time, file)] of a .pvd, in its order."""
    return [(d.get("timestep"), d.get("file")) for d in ET.parse(pvd).getroot().iter("DataSet")]


# 1. A series of four samples against checkpoints of the same run at those steps.
steps = [0, 100, 200, 300]
out = lava_run("--steps", "300", "--series", os.path.join(scratch, "run"), "--every", "100")
pvd = os.path.join(scratch, "run.pvd")
entries = collection(pvd)
check([f for _, f in entries] == ["run/step_%012d.vtp" % k for k in steps],
      "run.pvd names the samples at steps 0, 100, 200, 300: %s" % entries)
check([float(t) for t, _ in entries] == [k * dt for k in steps],
      "the collection's times are step x dt: %s" % [t for t, _ in entries])
check(sorted(os.listdir(os.path.join(scratch, "run"))) == sorted(os.path.basename(f) for _, f in entries),
      "the folder holds exactly the samples the collection names")
ends = np.cumsum(capacities)
scene_hashes = set()
for k in steps:
    ck = os.path.join(scratch, "at%d.npz" % k)
    printed = lava_run("--steps", str(k), "--checkpoint", ck)
    z = np.load(ck)
    state, alive = z["state"], z["state"][:, 6] >= 0
    slots = np.nonzero(alive)[0]
    n, a, fields = read_sample(os.path.join(scratch, "run", "step_%012d.vtp" % k))
    name = "step %d: " % k
    check(n == len(slots), name + "%d points, %d alive in the checkpoint" % (n, len(slots)))
    check(same_bits(a["Points"], state[alive, 0:3]), name + "positions")
    check(same_bits(a["velocity"], state[alive, 3:6]), name + "velocity")
    check(same_bits(a["age"], state[alive, 6]), name + "age")
    v = state[alive, 3:6].astype("f8")
    speed = np.sqrt(v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1] + v[:, 2] * v[:, 2]).astype("f4")
    check(same_bits(a["speed"], speed), name + "speed, |v| in double rounded once")
    check(same_bits(a["slot"], slots.astype("i8")), name + "slot")
    check(same_bits(a["emitter"], np.searchsorted(ends, slots, side="right").astype("i4")),
          name + "emitter")
    check(same_bits(a["temperature"], z["temperature"][alive]), name + "temperature")
    check(same_bits(a["crust"], z["crust"][alive]), name + "crust")
    check(fields.get("step") == k, name + "field step %s" % fields.get("step"))
    check(fields.get("TimeValue") == k * dt, name + "field TimeValue %s" % fields.get("TimeValue"))
    check("state hash %016x" % fields.get("state_hash", 0) in printed,
          name + "field state_hash, the hash the run prints")
    scene_hashes.add(fields.get("scene_hash"))
    if k == 300:
        check("state hash %016x" % fields.get("state_hash", 0) in out, "the series run's hash")
check(len(scene_hashes) == 1 and 0 not in scene_hashes, "one scene hash: %s" % scene_hashes)
print("series: %d samples equal the checkpoints at their steps" % len(steps))

# 2. Interrupted by SIGINT, then resumed: whole files only, and the straight run's bytes.
long = os.path.join(scratch, "long")
ck = os.path.join(scratch, "long.npz")
child = subprocess.Popen([lava, *common, "--steps", "1000000", "--backend", "cpu", "--threads",
                          "1", "--series", long, "--every", "20", "--checkpoint", ck],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
deadline = time.time() + 60
while time.time() < deadline and (not os.path.exists(long + ".pvd")
                                  or len(collection(long + ".pvd")) < 3):
    time.sleep(0.05)
child.send_signal(signal.SIGINT)
stdout, stderr = child.communicate(timeout=60)
check(child.returncode == 130, "SIGINT: exit %d, 130 expected: %s" % (child.returncode, stderr))
named = [os.path.basename(f) for _, f in collection(long + ".pvd")]
check(sorted(os.listdir(long)) == named, "after SIGINT the folder holds exactly the named samples")
for f in named:
    read_sample(os.path.join(long, f))
stopped = int(np.load(ck)["step"])
end = (stopped // 20 + 3) * 20 + 7  # three samples more, and steps past the last
lava_run("--resume", ck, "--steps", str(end - stopped), "--backend", "cpu", "--series", long,
         "--every", "20", resume=True)
straight = os.path.join(scratch, "straight")
lava_run("--steps", str(end), "--backend", "cpu", "--series", straight, "--every", "20")
names = sorted(os.listdir(straight))
check(sorted(os.listdir(long)) == names and len(names) == end // 20 + 1,
      "the resumed series has the straight run's %d samples" % len(names))
for f in names:
    resumed = os.path.join(long, f)
    check(os.path.exists(resumed) and
          open(resumed, "rb").read() == open(os.path.join(straight, f), "rb").read(),
          "resumed %s has the straight run's bytes" % f)
check(open(long + ".pvd").read().replace("long/", "") ==
      open(straight + ".pvd").read().replace("straight/", ""),
      "the resumed collection is the straight run's")
print("series: stopped at step %d by SIGINT, resumed to step %d: %d samples as a straight run's"
      % (stopped, end, len(names)))
# 3. `lava render --series`: the samples of the steps its frames took, the same bytes as
# simulate's; and `render --resume` continues a series a checkpoint left. A step of 2^-10 s
# and 8 frames a second: 128 steps a frame, exactly.
fine = ["--scene", scene, "--dt", "0.0009765625"]


def run_program(*args):
    done = subprocess.run([lava, *args], capture_output=True, text=True)
    check(done.returncode == 0, "lava %s: %s" % (" ".join(args), done.stderr))


frames = os.path.join(scratch, "frames")
series = {name: os.path.join(scratch, name) for name in ("rendered", "simulated", "resumed")}
shown = ["render", "--frames", "3", "--fps", "8", "--size", "32x18", "--out", frames]
run_program(*shown, *fine, "--warmup", "0.125", "--series", series["rendered"], "--every", "64")
run_program("simulate", *fine, "--steps", "384", "--series", series["simulated"], "--every", "64")
ck = os.path.join(scratch, "at128.npz")
run_program("simulate", *fine, "--steps", "128", "--checkpoint", ck, "--series",
            series["resumed"], "--every", "64")
run_program(*shown, "--resume", ck, "--warmup", "0", "--series", series["resumed"], "--every",
            "64")
simulated = sorted(os.listdir(series["simulated"]))
check(simulated == ["step_%012d.vtp" % k for k in range(0, 385, 64)],
      "simulate wrote samples 0 to 384: %s" % simulated)
for run in ("rendered", "resumed"):
    names = sorted(os.listdir(series[run]))
    check(names == simulated, "render's series %s has simulate's samples: %s" % (run, names))
    for f in simulated:
        mine = os.path.join(series[run], f)
        check(os.path.exists(mine) and open(mine, "rb").read() ==
              open(os.path.join(series["simulated"], f), "rb").read(),
              "render's %s/%s has simulate's bytes" % (run, f))
print("series: render and render --resume write simulate's samples")
if failures:
    sys.exit("FAIL: %d checks" % len(failures))
print("PASS")
