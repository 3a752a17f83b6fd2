#!/usr/bin/env bash
# The demo in a real window under Xvfb on lavapipe, with each line renderer: hundreds of
# frames with resizes, a minimise and a restore (--exercise), validation and
# synchronization validation on (any message makes lava exit 1). Passes on exit 0 and the
# summary line.
set -u
lava=$1
for renderer in lines splat; do
  out=$(xvfb-run -a -s "-screen 0 1600x1000x24" "$lava" demo --frames 400 --size 800x450 \
        --exercise --renderer "$renderer" --particles 20000 --rate 4000 2>&1)
  status=$?
  echo "$renderer: $out"
  [ $status -eq 0 ] || { echo "FAIL: lava demo --renderer $renderer exited $status"; exit 1; }
  echo "$out" | grep -Eq '^demo: 400 frames in [0-9.]+ s, average [0-9.]+ fps' ||
    { echo "FAIL: no summary line"; exit 1; }
  echo "$out" | grep -q 'rendering headless' && { echo "FAIL: no window was opened"; exit 1; }
done
exit 0
