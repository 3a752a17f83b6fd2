#!/usr/bin/env bash
# The installed libraries on a fresh prefix: `cmake --install` of this build; its include/ holds only
# lava/; the scenes under share/lava/scenes, named by the CMake package and pkg-config; liblava
# (Lava::lava, pkg-config lava) and liblava_tools beside it (Lava::lava_tools, lava_tools);
# every symbol of each is lava's or a dependency's; examples/embed and examples/renderpass
# link Lava::lava alone, examples/headless Lava::lava_tools; examples/embed,
# examples/headless and examples/renderpass configure, build and run against it with
# find_package(Lava) (the render-pass host in a window under Xvfb, resized as it runs); the
# headless example also builds as one file with `pkg-config --cflags --libs lava_tools`. The
# examples run on the pinned driver with the validation layer and synchronization
# validation (embed and renderpass fail on a message).
set -euo pipefail
build=$1
source=$2
flags=${3:-}  # compiler flags the examples need too (a sanitized build's)
# ${@:4}: ICD manifests of further implementations to run the embed example on
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null
extra=$(find "$prefix/include" -mindepth 1 -maxdepth 1 ! -name lava)
[ -z "$extra" ] || { echo "FAIL: include/ holds more than lava/: $extra"; exit 1; }
[ -f "$prefix/include/lava/lava.h" ] || { echo "FAIL: no lava/lava.h"; exit 1; }
[ -f "$prefix/lib/cmake/Lava/LavaConfigVersion.cmake" ] || { echo "FAIL: no version file"; exit 1; }
for scene in crater volcano fountain vortex room modules/all; do
  [ -f "$prefix/share/lava/scenes/$scene.toml" ] || { echo "FAIL: $scene.toml not installed"; exit 1; }
done
for name in lava lava_tools; do
  library=$(readlink -f "$prefix/lib/lib$name.so")
  readelf -d "$library" | grep -q "SONAME.*lib$name.so.0" || { echo "FAIL: lib$name has no SONAME"; exit 1; }
  /usr/bin/python3 "$source/tests/check_symbols.py" "$library"
done

for example in embed headless renderpass; do
  cmake -S "$source/examples/$example" -B "$work/$example" -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="$flags" >/dev/null
  cmake --build "$work/$example" -j2 >/dev/null
  [ $example = renderpass ] && continue  # it needs a window: below
  out=$("$work/$example/lava_$example")
  echo "$out"
done
echo "$out" | grep -q "bit-identical" || { echo "FAIL: headless did not compare"; exit 1; }
# A host of Lava::lava alone needs no tools library; the tools' host gets both.
for example in embed renderpass; do
  if readelf -d "$work/$example/lava_$example" | grep -q 'NEEDED.*liblava_tools'; then
    echo "FAIL: $example links liblava_tools"; exit 1
  fi
done
readelf -d "$work/headless/lava_headless" | grep -q 'NEEDED.*liblava_tools.so.0' ||
  { echo "FAIL: headless does not link liblava_tools"; exit 1; }

# The render-pass host: 240 frames in a window, made smaller after its first second.
cat > "$work/renderpass.sh" <<RUN
"$work/renderpass/lava_renderpass" 240 > "$work/renderpass.txt" 2>&1 &
pid=\$!
window=\$(timeout 60 xdotool search --sync --name '^Lava in render passes\$' | head -1)
sleep 1
[ -n "\$window" ] && xdotool windowsize "\$window" 480 270
wait \$pid
RUN
status=0
xvfb-run -a -s "-screen 0 800x600x24" bash "$work/renderpass.sh" || status=$?
cat "$work/renderpass.txt"
[ $status -eq 0 ] || { echo "FAIL: the render-pass example exited $status"; exit 1; }
grep -q "at 480x270, .* bit-identical" "$work/renderpass.txt" ||
  { echo "FAIL: the render-pass example did not draw at its new size"; exit 1; }

# Validation turned on the usual way as well: the loader's notice about it is no failure.
VK_INSTANCE_LAYERS=VK_LAYER_KHRONOS_validation \
  VK_LAYER_ENABLES=VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT \
  "$work/embed/lava_embed" >/dev/null

# The embed example on the other Vulkan implementations given (tests/drivers), each its own
# instance and device with the validation layer (a message fails it).
for icd in "${@:4}"; do
  VK_DRIVER_FILES=$icd VK_ICD_FILENAMES=$icd "$work/embed/lava_embed"
done

# One file and pkg-config, as a Makefile would do it.
export PKG_CONFIG_PATH=$prefix/lib/pkgconfig
[ "$(pkg-config --variable=scenesdir lava)" -ef "$prefix/share/lava/scenes" ] ||
  { echo "FAIL: pkg-config's scenesdir is $(pkg-config --variable=scenesdir lava)"; exit 1; }
if pkg-config --cflags lava | grep -q -- '-std='; then
  echo "FAIL: lava.pc sets a language standard: $(pkg-config --cflags lava)"; exit 1
fi
pkg-config --exists lava_tools || { echo "FAIL: pkg-config does not find lava_tools"; exit 1; }
c++ -std=c++20 "$source/examples/headless/headless.cpp" $flags $(pkg-config --cflags --libs lava_tools) \
    -Wl,-rpath,"$prefix/lib" -o "$work/one-file"
"$work/one-file"
echo "PASS"
