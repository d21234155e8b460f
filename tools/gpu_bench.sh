#!/usr/bin/env bash
# The GPU benchmark, in one short run: Autzen (spheres 0.8 m across) and 5 M generated points,
# ODS and mono at 3840×1920 per eye, every rasterizer mode on Autzen and the exact and the
# paper's fastest mode on 5 M points, each with the median frame and the sustained frame rate
# over many frames, and the live stream (examples/live_bench, 1 and 4 walking clients at
# LIVE_WIDTH, default 2048 per eye); the ODS runs also time a mono frame after each pair (the
# stereo / mono column). Results (bench.md/csv/json and charts per run, plus summary.md naming the
# adapter) go to OUT, which docs/BENCHMARKS.md quotes.
#
#   tools/gpu_bench.sh [OUT]            (default OUT: docs/bench/gpu)
#   WIDTH=1024 POINTS=200000 FRAMES=5 tools/gpu_bench.sh /tmp/b   (a quick check)
#
# On a machine without Rust or a Vulkan loader (the lent GPU machine), run tools/gpu_bundle.sh
# here first and carry .gpu: without cargo the script takes the binaries from .gpu/bin, unpacks the
# loader from .gpu/debs when the machine has none, and points Vulkan at the NVIDIA driver. It
# stops before the long runs when the adapter is a software one while nvidia-smi sees a GPU
# (REQUIRE_GPU=0 lets it run anyway). When $OUT is set (the device tool's result folder), it
# also leaves summary.md and all results as gpu_bench.tgz there.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/bench/gpu}
width=${WIDTH:-3840}
points=${POINTS:-5000000}
frames=${FRAMES:-60}
warmup=${WARMUP:-5}
live_width=${LIVE_WIDTH:-2048}
started=$SECONDS
PATH=$PATH:/usr/sbin:/sbin

if command -v cargo >/dev/null; then
  cargo build --release --quiet --bin omnicloud --example gen_big_las --example live_bench
  bin=target/release/omnicloud
  gen=target/release/examples/gen_big_las
  live=target/release/examples/live_bench
elif [ -x .gpu/bin/omnicloud ] && [ -x .gpu/bin/gen_big_las ]; then
  bin=.gpu/bin/omnicloud
  gen=.gpu/bin/gen_big_las
  live=.gpu/bin/live_bench
else
  echo "gpu_bench: no cargo here and no .gpu bundle: run tools/gpu_bundle.sh where Rust is" \
    "and carry .gpu" >&2
  exit 2
fi
if ! ldconfig -p | grep -q 'libvulkan\.so\.1'; then
  debs=(.gpu/debs/*.deb)
  if [ -e "${debs[0]}" ]; then
    for f in "${debs[@]}"; do dpkg -x "$f" /; done
    ldconfig
  else
    echo "gpu_bench: no Vulkan loader (libvulkan.so.1) and none in .gpu/debs" >&2
  fi
fi
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" ] && [ -f "$nvidia_icd" ]; then
  export VK_DRIVER_FILES=$nvidia_icd
fi
has_nvidia=0
command -v nvidia-smi >/dev/null && nvidia-smi -L >/dev/null 2>&1 && has_nvidia=1
require_gpu=${REQUIRE_GPU:-$has_nvidia}

big=${TMPDIR:-/tmp}/omnicloud_bench_${points}.las
[ -f "$big" ] || "$gen" "$big" "$points"
mkdir -p "$out"

# Which adapter the runs will get: a one-frame bench, before minutes are spent on the others.
probe=$(mktemp -d)
"$bin" bench data/autzen_trim.laz --width 256 --modes bounds+raycast --frames 1 --warmup 0 \
  --out "$probe" --quiet
adapter=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["adapter"])' \
  "$probe/bench.json")
rm -rf "$probe"
echo "gpu_bench: adapter $adapter" >&2
if [ "$require_gpu" = 1 ] && grep -qiE 'llvmpipe|lavapipe|swiftshader|softpipe' <<<"$adapter"; then
  echo "gpu_bench: $adapter is a software adapter but a GPU is here: Vulkan did not find" \
    "its driver (VK_DRIVER_FILES=${VK_DRIVER_FILES:-unset}); REQUIRE_GPU=0 runs anyway" >&2
  exit 3
fi

fast=bounds+raycast,quad+sprite
run() { # NAME SCENE STEREO MODES [extra bench options]
  local name=$1 scene=$2 stereo=$3 modes=$4
  shift 4
  local args=(bench "$scene" --width "$width" --stereo "$stereo" --warmup "$warmup"
    --frames "$frames" --out "$out/$name" --quiet "$@")
  [ "$modes" = all ] || args+=(--modes "$modes")
  local t=$SECONDS
  echo "== $name" >&2
  "$bin" "${args[@]}"
  echo "   $name took $((SECONDS - t)) s" >&2
}
run autzen_ods  data/autzen_trim.laz ods  all   --radius 0.4
run autzen_mono data/autzen_trim.laz none all   --radius 0.4
run big_ods     "$big"               ods  $fast
run big_mono    "$big"               none $fast
# The live stream: walking clients (serve's --live-scale 1); a failure leaves its message.
if [ -x "${live:-}" ]; then
  echo "== live" >&2
  "$live" data/autzen_trim.laz --width "$live_width" --clients 1,4 --seconds 20 \
    > "$out/live.txt" 2>&1 || echo "live_bench failed" >> "$out/live.txt"
fi

{
  echo "# GPU benchmark"
  echo
  echo "- date: $(date -u +%Y-%m-%dT%H:%MZ); command: \`tools/gpu_bench.sh\` (WIDTH=$width POINTS=$points FRAMES=$frames WARMUP=$warmup)"
  command -v nvidia-smi >/dev/null && echo "- GPU: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1)"
  echo "- adapter: $adapter"
  echo "- CPU: $(nproc) cores; $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
  echo
  echo "| run | mode | median frame ms | fps (median) | sustained fps | stereo / mono | coverage mismatch |"
  echo "|---|---|---:|---:|---:|---:|---:|"
  for name in autzen_ods autzen_mono big_ods big_mono; do
    python3 - "$out/$name/bench.json" "$name" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print(f"<!-- {sys.argv[2]}: {r['points']} points, {r['width']}x{r['height']} {r['stereo']}, adapter {r['adapter']} -->")
for m in r["modes"]:
    mode = m["mode"]
    label = mode if isinstance(mode, str) else "+".join(str(v) for v in mode.values())
    mono = m.get("mono_frame_ms")
    ratio = f"{m['frame_ms'] / mono:.2f}" if mono else "–"
    print(f"| {sys.argv[2]} | {label} | {m['frame_ms']:.3f} | {m['fps']:.1f} | {m['sustained_fps']:.1f} | {ratio} | {m['accuracy']['coverage_mismatch']:.2e} |")
PY
  done
  if [ -f "$out/live.txt" ]; then
    echo
    echo "Live stream (\`examples/live_bench\`, Autzen, $live_width per eye, --live-scale 1):"
    echo
    sed 's/^/    /' "$out/live.txt"
  fi
} > "$out/summary.md"
cat "$out/summary.md"
echo "gpu_bench: done in $((SECONDS - started)) s" >&2
if [ -n "${OUT:-}" ] && [ -d "$OUT" ]; then
  cp "$out/summary.md" "$OUT/summary.md"
  tar czf "$OUT/gpu_bench.tgz" -C "$out" .
fi
