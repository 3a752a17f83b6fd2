#!/usr/bin/env bash
# The Python package as users install it: `pip install --no-build-isolation .` into a fresh
# venv (Debian's python3, its numpy from the system), imported from another folder with no
# PYTHONPATH or LD_LIBRARY_PATH, the Python tests and docs/python_example.py run against it
# (the presets found by name); then a wheel built with
# python3-build installs into another fresh venv and runs.
set -euo pipefail
build=$1   # this checkout's configured build, reused by setup.py
source=$2
lava=$3    # the program, for the tests that compare with it
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset PYTHONPATH LD_LIBRARY_PATH
export LAVA_BUILD_DIR=$build

/usr/bin/python3 -m venv --system-site-packages "$work/venv"
(cd "$source" && "$work/venv/bin/pip" install -q --no-build-isolation .)
cd "$work"
where=$("$work/venv/bin/python" -c "import lava; print(lava.__file__)")
case $where in
  "$work/venv/"*) ;;
  *) echo "FAIL: lava was imported from $where, not the venv"; exit 1 ;;
esac
shape=$("$work/venv/bin/python" -c "import lava; print(lava.simulate(100).shape)")
[ "$shape" = "(5000, 7)" ] || { echo "FAIL: lava.simulate(100).shape is $shape"; exit 1; }
LAVA_EXE=$lava "$work/venv/bin/python" -m pytest -q -p no:cacheprovider "$source/tests/python"
# The presets by name and docs/python_example.py, from a folder outside the repository.
"$work/venv/bin/python" -c "import lava; assert lava.Scene('volcano').particles == 36000"
mkdir "$work/example"
"$work/venv/bin/python" "$source/docs/python_example.py" "$work/example"
for picture in python-render.png python-trajectory.png python-flow.png; do
  [ -s "$work/example/$picture" ] || { echo "FAIL: the example wrote no $picture"; exit 1; }
done

(cd "$source" && /usr/bin/python3 -m build --no-isolation --wheel --outdir "$work/dist" . \
   > "$work/build.log" 2>&1) || { cat "$work/build.log"; echo "FAIL: no wheel"; exit 1; }
/usr/bin/python3 -m venv --system-site-packages "$work/wheel-venv"
"$work/wheel-venv/bin/pip" install -q "$work"/dist/lava-*.whl
"$work/wheel-venv/bin/python" -c "
import importlib.metadata, lava
assert lava.__version__ == importlib.metadata.version('lava'), lava.__version__
assert lava.render(frames=1, size=(32, 18), warmup=0.1)[0].shape == (18, 32, 3)
assert lava.Scene('eruption') == lava.Scene.from_toml(lava.Scene('eruption').to_toml())
print('wheel: lava', lava.__version__, 'from', lava.__file__)"
echo PASS
