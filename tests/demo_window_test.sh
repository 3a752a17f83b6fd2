#!/usr/bin/env bash
# The demo in a real window under Xvfb on lavapipe, validation and synchronization
# validation on (any message makes lava exit 1):
# 1. each line renderer and each presentation path for 400 frames with resizes, a minimise
#    and a restore (--exercise);
# 2. without MIT-SHM on the server: the swapchain is chosen, and --present shm is refused;
#    on a 16-bit display, which no path can present to, the demo renders headless;
# 3. the keyboard: P (screenshot), Space (pause), N (step), R (reset), H (hide the panel)
#    and Esc (quit), typed with xdotool into the focused window; the screenshot must appear;
#    then one Esc tap while frames are slow (a tap shorter than a frame must not be lost).
set -u
lava=$1
fault_layer=$2  # the folder of VK_LAYER_LAVA_fault's manifest
screen="-screen 0 1600x1000x24"

summary() {  # the demo's own summary line, or fail
  echo "$1" | grep -Eq "^demo: $2 frames in [0-9.]+ s, average [0-9.]+ fps" ||
    { echo "FAIL: no summary line"; exit 1; }
  echo "$1" | grep -q 'rendering headless' && { echo "FAIL: no window was opened"; exit 1; }
}

for run in "lines swapchain mailbox" "splat shm MIT-SHM"; do
  set -- $run
  out=$(xvfb-run -a -s "$screen" "$lava" demo --frames 400 --size 800x450 \
        --exercise --renderer "$1" --present "$2" --particles 20000 --rate 4000 2>&1)
  status=$?
  echo "$1, $2: $out"
  [ $status -eq 0 ] || { echo "FAIL: lava demo --renderer $1 --present $2 exited $status"; exit 1; }
  summary "$out" 400
  echo "$out" | grep -q ", $3; GPU" || { echo "FAIL: not presented by $3"; exit 1; }
done

# The panel's GPU times come from timestamps each frame copies into memory the host reads
# after the frame's fence: no vkGetQueryPoolResults per frame (lavapipe drains the queue
# there, which left one frame in flight). Counted by the fault layer ($2), failing nothing.
# Ten frames take less than the 0.1 s between timed frames: the last frame of a run of
# --frames N is timed too, so the summary has its GPU times however fast the host.
counts=$(mktemp)
out=$(xvfb-run -a -s "$screen" env LAVA_VALIDATION=0 VK_LAYER_PATH="$fault_layer" \
      VK_INSTANCE_LAYERS=VK_LAYER_LAVA_fault LAVA_FAULT_COUNTS="$counts" \
      "$lava" demo --frames 10 --size 320x180 2>&1)
status=$?
echo "timestamps: $out"
[ $status -eq 0 ] || { echo "FAIL: lava demo under the fault layer exited $status"; exit 1; }
grep -q '^vkQueueSubmit ' "$counts" || { echo "FAIL: the fault layer counted no calls"; exit 1; }
queries=$(sed -n 's/^vkGetQueryPoolResults \([0-9]*\).*/\1/p' "$counts")
rm -f "$counts"
[ "${queries:-0}" -eq 0 ] ||
  { echo "FAIL: the demo called vkGetQueryPoolResults $queries times"; exit 1; }
draw=$(echo "$out" | sed -n 's/.*GPU per frame: simulate [0-9.]* ms, draw \([0-9.]*\) ms.*/\1/p')
awk -v d="${draw:-0}" 'BEGIN { exit !(d > 0) }' ||
  { echo "FAIL: no GPU draw time read from the timestamps"; exit 1; }

# The default on lavapipe is MIT-SHM; a server without it gets the swapchain.
out=$(xvfb-run -a -s "$screen" "$lava" demo --frames 30 --size 320x180 2>&1)
echo "default: $out"
echo "$out" | grep -q ", MIT-SHM; GPU" || { echo "FAIL: lavapipe on Xvfb did not pick MIT-SHM"; exit 1; }
# Unless the user chose LP_NUM_THREADS, the demo runs llvmpipe with two threads per core
# (and says so); a choice of the user's stands.
cores=$(nproc)
echo "$out" | grep -q "^demo: LP_NUM_THREADS=$((2 * cores)) (llvmpipe, two threads per core" ||
  { echo "FAIL: the demo did not set LP_NUM_THREADS to twice the $cores cores"; exit 1; }
# llvmpipe's rasteriser threads in a running demo, with the environment "$@" added.
llvmpipe_threads() {
  xvfb-run -a -s "$screen" env "$@" sh -c '"$0" demo --size 160x90 > /dev/null 2>&1 & pid=$!
    for i in $(seq 150); do
      grep -qs "^llvmpipe-" /proc/$pid/task/*/comm && break; sleep 0.1
    done
    sleep 0.5; cat /proc/$pid/task/*/comm 2>/dev/null | grep -c "^llvmpipe-"
    kill $pid; wait $pid 2> /dev/null' "$lava"
}
threads=$(llvmpipe_threads LAVA_TEST=1)
[ "$threads" -eq $((2 * cores)) ] ||
  { echo "FAIL: the demo ran $threads llvmpipe threads, not $((2 * cores))"; exit 1; }
threads=$(llvmpipe_threads LP_NUM_THREADS=1)
[ "$threads" -eq 1 ] || { echo "FAIL: LP_NUM_THREADS=1 gave $threads llvmpipe threads"; exit 1; }
out=$(env LP_NUM_THREADS=1 xvfb-run -a -s "$screen" "$lava" demo --frames 10 --size 320x180 2>&1)
echo "$out" | grep -q "LP_NUM_THREADS" && { echo "FAIL: the user's LP_NUM_THREADS was not kept"; exit 1; }
out=$(xvfb-run -a -s "$screen -extension MIT-SHM" "$lava" demo --frames 30 --size 320x180 2>&1)
echo "no MIT-SHM: $out"
echo "$out" | grep -q ", mailbox; GPU" || { echo "FAIL: without MIT-SHM the swapchain was not used"; exit 1; }
# lava's own status, not xvfb-run's (which can fail to clean up after a quick exit).
out=$(xvfb-run -a -s "$screen -extension MIT-SHM" sh -c '"$0" "$@" 2>&1; echo "status $?"' \
      "$lava" demo --frames 30 --present shm 2>/dev/null)
status=$(echo "$out" | sed -n 's/^status //p')
out=$(echo "$out" | grep -v '^status ')
echo "no MIT-SHM, --present shm: $out"
[ $status -eq 2 ] || { echo "FAIL: --present shm without MIT-SHM exited $status, not 2"; exit 1; }
[ "$(echo "$out" | wc -l)" -eq 1 ] && echo "$out" | grep -q -- "--present" ||
  { echo "FAIL: expected one line naming --present"; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# A 16-bit display, which the driver cannot present to: headless frames, saying why.
out=$(xvfb-run -a -s "-screen 0 640x360x16" "$lava" demo --frames 2 --size 160x90 \
      --out "$work/depth16" 2>&1)
status=$?
echo "16-bit display: $out"
[ $status -eq 0 ] || { echo "FAIL: lava demo on a 16-bit display exited $status"; exit 1; }
echo "$out" | grep -q 'depth 24); rendering headless instead' ||
  { echo "FAIL: no reason given for rendering headless"; exit 1; }
[ -s "$work/depth16/frame_00001.png" ] || { echo "FAIL: no headless frames"; exit 1; }
# drive NAME "DEMO ARGS" 'KEYS': under Xvfb, starts lava demo with DEMO ARGS (its output in
# $work/NAME.txt), focuses its window, runs the xdotool commands KEYS (a shell snippet,
# run in $work) and waits for lava to exit; returns lava's exit status.
drive() {
  cat > "$work/$1.sh" <<DRIVE
cd "$work"
timeout 120 "$lava" demo $2 > $1.txt 2>&1 &
pid=\$!
window=\$(timeout 60 xdotool search --sync --name '^Lava\$' 2>/dev/null | head -1)
if [ -z "\$window" ]; then echo "no Lava window appeared" >> $1.txt; kill \$pid; exit 1; fi
xdotool windowfocus --sync "\$window"
$3
wait \$pid
DRIVE
  xvfb-run -a -s "$screen" bash "$work/$1.sh"
}

# Each key once (Space twice), one tap each, no retries: the demo counts what took effect.
drive keys "--size 640x360" '
sleep 0.5
for key in p space n r space h Escape; do xdotool key "$key"; sleep 0.2; done'
status=$?
out=$(cat "$work/keys.txt")
echo "keys: $out"
[ $status -eq 0 ] || { echo "FAIL: lava demo with keys exited $status"; exit 1; }
summary "$out" '[0-9]+'
[ -s "$work/lava-screenshot-000.png" ] || { echo "FAIL: P saved no screenshot"; exit 1; }
echo "$out" | grep -q 'saved lava-screenshot-000.png' || { echo "FAIL: no screenshot message"; exit 1; }
echo "$out" | grep -q 'keys took effect: pause 2, step 1, reset 1, panel 1, screenshot 1' ||
  { echo "FAIL: a key did not take effect exactly once"; exit 1; }

# The panel (drawn into an image of its own when it changes, copied over each frame): in
# the window, at its place, opaque (ImGui's window background, 15,15,15, behind its text);
# gone once H hides it. Read from the X server's screen, as a user sees it.
drive panel "--size 640x360 --warmup 3" '
sleep 1.5
xwd -root -silent > shown.xwd
xdotool key h
sleep 0.5
xwd -root -silent > hidden.xwd
xdotool key Escape'
status=$?
echo "panel: $(cat "$work/panel.txt")"
[ $status -eq 0 ] || { echo "FAIL: lava demo for the panel exited $status"; exit 1; }
python3 - "$work/shown.xwd" "$work/hidden.xwd" <<'CHECK' || exit 1
import struct, sys
def pixels(path):  # an XWD dump of the root window, 24-bit TrueColor: (w, h, rows)
    data = open(path, "rb").read()
    header = struct.unpack(">25I", data[:100])
    size, width, height, pitch, colors = header[0], header[4], header[5], header[12], header[19]
    first = size + 12 * colors
    return width, height, lambda x, y: tuple(data[first + y * pitch + 4 * x + 2 - c] for c in range(3))
def counts(path):  # within the panel's rectangle: background pixels and bright (text) ones
    w, h, at = pixels(path)
    background = bright = total = 0
    for y in range(30, 200, 2):
        for x in range(14, 380, 2):
            p = at(x, y)
            total += 1
            background += p == (15, 15, 15)
            bright += min(p) > 150
    return background / total, bright
shown, hidden = counts(sys.argv[1]), counts(sys.argv[2])
print("panel shown: %.0f%% background, %d bright; hidden: %.0f%% background, %d bright"
      % (100 * shown[0], shown[1], 100 * hidden[0], hidden[1]))
if not (shown[0] > 0.5 and shown[1] > 100): sys.exit("FAIL: the panel is not in the window")
if not (hidden[0] < 0.05): sys.exit("FAIL: the panel stayed after H")
CHECK

# One tap of Esc while frames are slow (262,144 lines through the graphics pipeline, over
# 100 ms each on lavapipe): pressed and released within one frame, it must still quit.
drive slow "--size 640x360 --renderer lines --particles 262144 --rate 100000 --warmup 3" '
sleep 1
xdotool key Escape'
status=$?
out=$(cat "$work/slow.txt")
echo "Esc on slow frames: $out"
[ $status -eq 0 ] || { echo "FAIL: one Esc tap on slow frames did not quit (exit $status)"; exit 1; }
summary "$out" '[0-9]+'
exit 0
