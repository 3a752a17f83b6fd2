#!/usr/bin/env bash
# The cross-driver checks of tests/drivers/CMakeLists.txt.
#
#   drivers_test.sh render LAVA SCENES OUT     the volcano, both renderers, into OUT/{lines,splat};
#                       the explicit flow's eruption at 3 s (the CPU reference's checkpoint,
#                       the device drawing its molten surface), both renderers at 640x360, into
#                       OUT/eruption-{lines,splat}
#   drivers_test.sh compare DIFF BASE OTHER SPLAT LINES ERUPTION-SPLAT ERUPTION-LINES
#                       OTHER's frames against BASE's (lavapipe 22.3's): at most SPLAT, LINES
#                       and the eruption's pixels, each "N:L" (N pixels differing by more than
#                       L levels)
#   drivers_test.sh hashes A.csv B.csv ...     every line of B.csv ... is one of A.csv's: the same
#                       hashes of the builtin suite's cases each ran
set -euo pipefail

case "$1" in
  render)
    lava=$2 scenes=$3 out=$4
    rm -rf "$out"
    mkdir -p "$out"
    "$lava" simulate --scene "$scenes/eruption-explicit.toml" --backend cpu --steps 3000 \
            --checkpoint "$out/eruption.npz" >/dev/null
    for renderer in lines splat; do
      "$lava" render --scene "$scenes/volcano.toml" --frames 1 --warmup 2 --renderer "$renderer" \
              --out "$out/$renderer" >/dev/null
      "$lava" render --resume "$out/eruption.npz" --frames 1 --warmup 0 --size 640x360 \
              --renderer "$renderer" --out "$out/eruption-$renderer" >/dev/null
    done
    ;;
  compare)
    diff=$2 base=$3 other=$4
    status=0
    for check in "splat:$5" "lines:$6" "eruption-splat:$7" "eruption-lines:$8"; do
      IFS=: read -r renderer pixels levels <<< "$check"
      echo -n "$renderer (at most $pixels pixels beyond $levels levels): "
      "$diff" "$base/$renderer/frame_00000.png" "$other/$renderer/frame_00000.png" "$pixels" \
              "$levels" "$other/$renderer/differences.png" || status=1
    done
    exit $status
    ;;
  hashes)
    shift
    first=$1
    shift
    for other in "$@"; do
      # Each of another driver's lines is one of the first's: the same hash at each
      # checkpoint of the cases it ran (SwiftShader runs some of them).
      foreign=$(grep -vxF -f "$first" "$other" || true)
      if [ -n "$foreign" ] || [ "$(wc -l < "$other")" -lt 2 ]; then
        echo "FAIL: $(basename "$other") differs from $(basename "$first"):"
        diff "$first" "$other" | head -20
        exit 1
      fi
    done
    echo "the same hashes from $(($# + 1)) drivers ($(($(wc -l < "$first") - 1)) lines in $(basename "$first"))"
    ;;
  *)
    echo "drivers_test.sh: unknown check $1" >&2
    exit 2
    ;;
esac
