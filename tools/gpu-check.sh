#!/usr/bin/env bash
# The GPU runbook: on a machine with a GPU and no package registry, run everything
# that proves Lava there and keep every result in one folder, within 5 minutes.
#
#   tools/gpu-check.sh [--dry] [--lava PATH] [--prefix DIR] OUT
#
#   --lava PATH    the lava binary (default: build/lava beside this script's repository)
#   --prefix DIR   Debian runtime libraries carried beside it, unpacked with dpkg -x (their
#                  usr/lib/x86_64-linux-gnu goes on LD_LIBRARY_PATH; usr/bin/Xvfb is used
#                  for the demo when the machine has none)
#   --dry          the same steps at small sizes (CI runs it on lavapipe)
#   OUT            folder for the results (created): env.txt, info.txt, suite.xml,
#                  suite.csv, validate-*.txt, bench*.json/.txt (bench-flow: the flow's rows),
#                  submission.txt (the longest submission of advance() at each flow size),
#                  render-*/ (render-flow: the eruption), demo.txt, summary.txt
#
# lava needs, beside glibc: libvulkan1, libglfw3, libx11-6, libxext6, libhwy1 (cpu-simd)
# and libstdc++6 from Debian 12 (ldd's "not found" lines land in env.txt).
#
# Point VK_DRIVER_FILES at the GPU's ICD (e.g. /usr/share/vulkan/icd.d/nvidia_icd.json) or
# let the loader find it; LAVA_DEVICE picks a device when there are several.
set -uo pipefail

here="$(cd "$(dirname "$0")/.." && pwd)"
lava="$here/build/lava"
prefix=""
dry=0
out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --dry) dry=1 ;;
    --lava) lava="$2"; shift ;;
    --prefix) prefix="$2"; shift ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    -*) echo "gpu-check: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) out="$1" ;;
  esac
  shift
done
[ -n "$out" ] || { echo "gpu-check: give the results folder (see --help)" >&2; exit 2; }
[ -x "$lava" ] || { echo "gpu-check: no lava binary at $lava (--lava PATH)" >&2; exit 2; }
mkdir -p "$out" || exit 2
if [ -n "$prefix" ]; then
  export LD_LIBRARY_PATH="$prefix/usr/lib/x86_64-linux-gnu:$prefix/lib/x86_64-linux-gnu${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  export PATH="$prefix/usr/bin:$PATH"
fi

if [ "$dry" = 1 ]; then
  sizes=65536,262144; steps=3000; particles=20000; demo_particles=20000; frames=60
  flow_sizes=1024; flow_warmup=0.2
  suite_cases=(--cases seed-scene,all)  # the whole suite is Drivers.*.BuiltinSuite's
else
  suite_cases=()
  sizes=1048576,16777216,67108864,268435456; steps=3000; particles=1048576
  demo_particles=262144; frames=600
  flow_sizes=16384,262144,1048576; flow_warmup=40
fi

failures=0
started=$(date +%s)
# step NAME COMMAND...: runs it with its output in OUT/NAME.txt, one summary line each.
step() {
  local name="$1"; shift
  local t0 t1 rc
  t0=$(date +%s%N)
  "$@" >"$out/$name.txt" 2>&1
  rc=$?
  t1=$(date +%s%N)
  printf '%-24s exit %3d  %6d ms  %s\n' "$name" "$rc" "$(( (t1 - t0) / 1000000 ))" \
    "$(tail -n 1 "$out/$name.txt" | cut -c1-100)" | tee -a "$out/summary.txt"
  [ "$rc" = 0 ] || failures=$((failures + 1))
  return 0
}

: >"$out/summary.txt"
{
  echo "date: $(date -u +%FT%TZ)"
  echo "host: $(uname -a)"
  echo "glibc: $(ldd --version 2>&1 | head -n 1)"
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //') x $(nproc)"
  echo "lava: $lava ($("$lava" --version 2>/dev/null || echo 'no --version'))"
  echo "VK_DRIVER_FILES=${VK_DRIVER_FILES:-} LAVA_DEVICE=${LAVA_DEVICE:-}"
  echo "LD_LIBRARY_PATH=${LD_LIBRARY_PATH:-}"
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total \
    --format=csv,noheader
  echo "missing libraries:"; ldd "$lava" | grep 'not found' || echo "  none"
} >"$out/env.txt" 2>&1
cat "$out/env.txt"

step info "$lava" info
step suite "$lava" validate --suite builtin "${suite_cases[@]}" --junit "$out/suite.xml" --results "$out/suite.csv"
step validate-exact "$lava" validate --scene "$here/docs/data/all-modules.toml" \
  --particles "$particles" --steps "$steps" --every 1000
step validate-ulp "$lava" validate --scene "$here/scenes/volcano.toml" --steps "$steps" \
  --every 1000 --tolerance-ulp 4
step bench "$lava" bench --sizes "$sizes" --steps 200 --backends gpu --json "$out/bench.json"
step bench-unfused "$lava" bench --sizes "${sizes%%,*}" --steps 50 --backends gpu \
  --steps-per-dispatch 1 --json "$out/bench-unfused.json"
# The GPU against the host's CPU on all its cores, SIMD lanes as wide as it runs.
step bench-cpu "$lava" bench --sizes "${sizes%%,*}" --steps 200 --backends gpu,cpu-simd-mt \
  --json "$out/bench-cpu.json"
# The flow: its passes' speed against the density sum alone, up to a million flow particles,
# and the eruption drawn after it has flowed and crusted.
step bench-flow "$lava" bench --flow --sizes "$flow_sizes" --steps 100 --backends gpu \
  --json "$out/bench-flow.json"
# The longest submission a blocking helper makes (2^26 particle-steps, GpuSimulationOptions)
# at each size, from the flow's rate: what a desktop driver's watchdog would see.
step submission awk -F'[:,]' '/"particles"/ {
    for (i = 1; i < NF; ++i) {
      if ($i ~ /"particles"/) n = $(i + 1) + 0
      if ($i ~ /"particle_steps_per_second"/) r = $(i + 1) + 0
    }
    steps = int(67108864 / n); if (steps < 1) steps = 1; if (steps > 4096) steps = 4096
    printf "flow %d particles: %d steps a submission, %.1f ms\n", n, steps, 1000 * steps * n / r
  }' "$out/bench-flow.json"
step render-flow "$lava" render --frames 2 --scene "$here/scenes/eruption-explicit.toml" \
  --warmup "$flow_warmup" --out "$out/render-flow"
step render-lines "$lava" render --frames 2 --renderer lines --out "$out/render-lines"
step render-splat "$lava" render --frames 2 --renderer splat --particles "$demo_particles" \
  --rate $((demo_particles / 5)) --warmup 5 --out "$out/render-splat"

# The demo in a real window: a running X server, else Xvfb (carried or installed).
display="${DISPLAY:-}"
xvfb_pid=""
if [ -z "$display" ] && command -v Xvfb >/dev/null; then
  display=":$((90 + RANDOM % 9))"
  Xvfb "$display" -screen 0 1280x720x24 -nolisten tcp >"$out/xvfb.txt" 2>&1 &
  xvfb_pid=$!
  sleep 1
fi
if [ -n "$display" ]; then
  step demo env DISPLAY="$display" "$lava" demo --frames "$frames" --warmup 5 \
    --particles "$demo_particles" --rate $((demo_particles / 5)) --present shm
  step demo-swapchain env DISPLAY="$display" "$lava" demo --frames "$frames" --warmup 5 \
    --particles "$demo_particles" --rate $((demo_particles / 5)) --present swapchain
else
  echo "demo: no X server and no Xvfb (carry xvfb's package in --prefix)" | tee -a "$out/summary.txt"
  failures=$((failures + 1))
fi
[ -n "$xvfb_pid" ] && kill "$xvfb_pid" 2>/dev/null

echo "gpu-check: $failures failed step(s), $(( $(date +%s) - started )) s; results in $out" |
  tee -a "$out/summary.txt"
[ "$failures" = 0 ]
