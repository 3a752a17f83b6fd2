#!/usr/bin/env bash
# The demo in a real window under Xvfb on lavapipe, validation and synchronization
# validation on (any message makes lava exit 1), driven from outside as a user would with
# xdotool, and judged by what the X server shows:
# 1. each line renderer and each presentation path through resizes (down to 1x1), a
#    minimise and a restore, under a window manager (twm: iconifying needs one), drawing
#    again at its size afterwards;
# 2. without MIT-SHM on the server: the swapchain is chosen, and --present shm is refused;
#    on a 16-bit display, which no path can present to, the demo renders headless;
# 3. the keyboard: H (hide the panel), Space (pause), N (step), R (reset), P (screenshot)
#    and Esc (quit), one tap each, each seen to take effect in the window's pixels; then
#    one Esc tap while frames are slow (a tap shorter than a frame must not be lost).
set -u
lava=$1
fault_layer=$2  # the folder of VK_LAYER_LAVA_fault's manifest
screen="-screen 0 1600x1000x24"

summary() {  # the demo's own summary line, or fail
  echo "$1" | grep -Eq "^demo: $2 frames in [0-9.]+ s, average [0-9.]+ fps" ||
    { echo "FAIL: no summary line"; exit 1; }
  echo "$1" | grep -q 'rendering headless' && { echo "FAIL: no window was opened"; exit 1; }
}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# xwd.py CHECK FILES: judges XWD dumps (24-bit TrueColor) of the Lava window.
cat > "$work/xwd.py" <<'XWD'
import struct, sys
def pixels(path):  # (width, height, rows of (r, g, b))
    data = open(path, "rb").read()
    header = struct.unpack(">25I", data[:100])
    size, width, height, pitch, colors = header[0], header[4], header[5], header[12], header[19]
    first = size + 12 * colors
    return width, height, [tuple(data[first + y * pitch + 4 * x + 2 - c] for c in range(3))
                           for y in range(height) for x in range(width)]
def lit(path):  # pixels of hot particles: bright red and orange
    return sum(1 for r, g, b in pixels(path)[2] if r > 200 and g > 100)
def changed(a, b):
    return sum(1 for p, q in zip(pixels(a)[2], pixels(b)[2]) if p != q)
check, files = sys.argv[1], sys.argv[2:]
if check == "drawn":  # the window shows the volcano and its particles
    n = lit(files[0])
    print("restored window: %d lit pixels" % n)
    if n < 200: sys.exit("FAIL: the restored window shows no particles")
elif check == "keys":
    def same(a, b): return changed(a + ".xwd", b + ".xwd") == 0
    print("lit pixels: stepped %d, reset %d" % (lit("stepped2.xwd"), lit("reset1.xwd")))
    if same("running1", "running2"): sys.exit("FAIL: the frames do not change while running")
    if not same("paused1", "paused2"): sys.exit("FAIL: Space did not pause")
    if same("paused2", "stepped1"): sys.exit("FAIL: N did not step")
    if not same("stepped1", "stepped2"): sys.exit("FAIL: N did not stay paused after its step")
    if not lit("reset1.xwd") * 4 < lit("stepped2.xwd"): sys.exit("FAIL: R did not reset")
    if not same("reset1", "reset2"): sys.exit("FAIL: R did not stay paused")
    if same("resumed1", "resumed2"): sys.exit("FAIL: Space did not resume")
def counts(path):  # in the panel's rectangle: background pixels and bright (text) ones
    w, h, rows = pixels(path)
    background = bright = total = 0
    for y in range(30, 200, 2):
        for x in range(14, 380, 2):
            p = rows[y * w + x]
            total += 1
            background += p == (15, 15, 15)
            bright += min(p) > 150
    return background / total, bright
def panel(c):
    return c[0] > 0.5 and c[1] > 100
if check == "panel-drawn":  # exit 0 once the window shows the panel
    sys.exit(0 if panel(counts(files[0])) else 1)
elif check == "panel":
    shown, hidden = counts("shown.xwd"), counts("hidden.xwd")
    print("panel shown: %.0f%% background, %d bright; hidden: %.0f%% background, %d bright"
          % (100 * shown[0], shown[1], 100 * hidden[0], hidden[1]))
    if not panel(shown): sys.exit("FAIL: the panel is not in the window")
    if not (hidden[0] < 0.05): sys.exit("FAIL: the panel stayed after H")
XWD

# drive NAME "DEMO ARGS" 'KEYS' [twm]: under Xvfb (with twm as the window manager when
# asked), starts lava demo with DEMO ARGS (its output in $work/NAME.txt), focuses its
# window ($window), runs the xdotool commands KEYS (a shell snippet, run in $work) and
# waits for lava to exit; returns lava's exit status.
drive() {
  cat > "$work/$1.sh" <<DRIVE
cd "$work"
if [ "${4:-}" = twm ]; then LC_ALL=C twm -f "$work/twmrc" > /dev/null 2>&1 & sleep 1; fi
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
# twm: no title bars, windows placed without asking, fonts any X server has.
printf '%s\n' RandomPlacement NoTitle 'TitleFont "fixed"' 'ResizeFont "fixed"' \
  'MenuFont "fixed"' 'IconFont "fixed"' 'IconManagerFont "fixed"' > "$work/twmrc"

# The window managed: smaller, 1x1, minimised (the window manager says Iconic, and the
# demo, drawing nothing, takes a fraction of the CPU time it took shown), restored and back
# to its size, drawing.
for run in "lines swapchain mailbox" "splat shm MIT-SHM"; do
  set -- $run
  drive "wm-$1" "--size 800x450 --renderer $1 --present $2 --particles 20000 --rate 4000" '
demo=$(pgrep -P $pid)  # lava, under timeout
cpu() { awk "{ print \$14 + \$15 }" /proc/$demo/stat; }  # its CPU time, in ticks
busy() { a=$(cpu); sleep 1; echo $(($(cpu) - a)) > "$1"; }
sleep 1
for size in "600 338" "400 150"; do xdotool windowsize "$window" $size; sleep 0.5; done
busy cpu-shown.txt
xdotool windowsize "$window" 1 1; sleep 0.5
xdotool windowminimize --sync "$window"; sleep 0.5
xprop -id "$window" WM_STATE | grep "window state" > state-minimised.txt
busy cpu-minimised.txt
xdotool windowmap --sync "$window"; sleep 0.5
xprop -id "$window" WM_STATE | grep "window state" > state-restored.txt
xdotool windowsize "$window" 800 450; sleep 1
xwd -id "$window" -silent > restored.xwd
xdotool windowfocus --sync "$window"; xdotool key Escape' twm
  status=$?
  out=$(cat "$work/wm-$1.txt")
  echo "$1, $2: $out"
  [ $status -eq 0 ] || { echo "FAIL: lava demo --renderer $1 --present $2 exited $status"; exit 1; }
  summary "$out" '[0-9]+'
  echo "$out" | grep -q "(800x450, 20000 particles, .*, $3; GPU" ||
    { echo "FAIL: not presented by $3 at 800x450 at the end"; exit 1; }
  grep -q Iconic "$work/state-minimised.txt" || { echo "FAIL: the window was not minimised"; exit 1; }
  grep -q Normal "$work/state-restored.txt" || { echo "FAIL: the window was not restored"; exit 1; }
  shown=$(cat "$work/cpu-shown.txt") minimised=$(cat "$work/cpu-minimised.txt")
  echo "CPU ticks in 1 s: shown $shown, minimised $minimised"
  [ $((4 * minimised)) -lt "$shown" ] || { echo "FAIL: the demo kept drawing while minimised"; exit 1; }
  python3 "$work/xwd.py" drawn "$work/restored.xwd" || exit 1
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
# The implicit flow, which the GPU does not step: the CPU steps it and the device draws each
# frame's state in the window, saying so, with the validation layers silent.
implicit="$work/implicit.toml"
sed 's/^solver = "explicit"/solver = "implicit"/' "$(dirname "$0")/../scenes/modules/flow.toml" > "$implicit"
grep -q '^solver = "implicit"' "$implicit" || { echo "FAIL: flow.toml names no explicit solver"; exit 1; }
out=$(xvfb-run -a -s "$screen" "$lava" demo --scene "$implicit" --frames 20 --size 320x180 2>&1)
status=$?
echo "implicit flow: $out"
[ $status -eq 0 ] || { echo "FAIL: lava demo of the implicit flow exited $status"; exit 1; }
summary "$out" 20
echo "$out" | grep -q "^demo: cpu-simd steps the run on [0-9]* threads* (the implicit flow has no GPU shader yet)" ||
  { echo "FAIL: the demo did not say that the CPU steps the implicit flow"; exit 1; }
echo "$out" | grep -q "GPU per frame: draw [0-9.]* ms; cpu-simd steps: [0-9.]* ms" ||
  { echo "FAIL: no CPU step time in the summary"; exit 1; }
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

# A 16-bit display, which the driver cannot present to: headless frames, saying why.
out=$(xvfb-run -a -s "-screen 0 640x360x16" "$lava" demo --frames 2 --size 160x90 \
      --out "$work/depth16" 2>&1)
status=$?
echo "16-bit display: $out"
[ $status -eq 0 ] || { echo "FAIL: lava demo on a 16-bit display exited $status"; exit 1; }
echo "$out" | grep -q 'depth 24); rendering headless instead' ||
  { echo "FAIL: no reason given for rendering headless"; exit 1; }
[ -s "$work/depth16/frame_00001.png" ] || { echo "FAIL: no headless frames"; exit 1; }
# Each key once (Space twice), one tap each, no retries, each judged by the window's
# pixels: running frames differ; paused ones do not; N steps once and stays paused; R
# empties the volcano (nothing emitted yet); P writes the screenshot; Space resumes.
drive keys "--size 640x360" '
cap() { xwd -id "$window" -silent > $1.xwd; }
sleep 1; xdotool key h; sleep 0.5
cap running1; sleep 0.5; cap running2
xdotool key space; sleep 0.5; cap paused1; sleep 0.5; cap paused2
xdotool key n; sleep 0.5; cap stepped1; sleep 0.5; cap stepped2
xdotool key r; sleep 0.5; cap reset1; sleep 0.5; cap reset2
xdotool key p; sleep 0.5
xdotool key space; sleep 0.5; cap resumed1; sleep 0.5; cap resumed2
xdotool key Escape'
status=$?
out=$(cat "$work/keys.txt")
echo "keys: $out"
[ $status -eq 0 ] || { echo "FAIL: lava demo with keys exited $status"; exit 1; }
summary "$out" '[0-9]+'
[ -s "$work/lava-screenshot-000.png" ] || { echo "FAIL: P saved no screenshot"; exit 1; }
echo "$out" | grep -q 'saved lava-screenshot-000.png' || { echo "FAIL: no screenshot message"; exit 1; }
(cd "$work" && python3 xwd.py keys) || exit 1

# The panel (drawn into an image of its own when it changes, copied over each frame): in
# the window, at its place, opaque (ImGui's window background, 15,15,15, behind its text);
# gone once H hides it. Read from the X server, as a user sees it.
drive panel "--size 640x360 --warmup 3" '
for i in $(seq 40); do  # the first frame follows the warm-up (slow under the sanitizers)
  sleep 0.5
  xwd -id "$window" -silent > shown.xwd
  python3 xwd.py panel-drawn shown.xwd && break
done
xdotool key h
sleep 0.5
xwd -id "$window" -silent > hidden.xwd
xdotool key Escape'
status=$?
echo "panel: $(cat "$work/panel.txt")"
[ $status -eq 0 ] || { echo "FAIL: lava demo for the panel exited $status"; exit 1; }
(cd "$work" && python3 xwd.py panel) || exit 1

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
