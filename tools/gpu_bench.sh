#!/usr/bin/env bash
# The GPU benchmark, in one short run: Autzen (spheres 0.8 m across) and 5 M generated points,
# ODS and mono at 3840×1920 per eye, every rasterizer mode on Autzen and the exact and the
# paper's fastest mode on 5 M points, each with the median frame and the sustained frame rate
# over many frames; the ODS runs also time a mono frame after each pair (the stereo / mono
# column). Results (bench.md/csv/json and charts per run, plus summary.md naming the
# adapter) go to OUT, which docs/BENCHMARKS.md quotes.
#
#   tools/gpu_bench.sh [OUT]            (default OUT: docs/bench/gpu)
#   WIDTH=1024 POINTS=200000 FRAMES=5 tools/gpu_bench.sh /tmp/b   (a quick check)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs/bench/gpu}
width=${WIDTH:-3840}
points=${POINTS:-5000000}
frames=${FRAMES:-60}
warmup=${WARMUP:-5}

cargo build --release --quiet --bin omnicloud --example gen_big_las
bin=target/release/omnicloud
big=${TMPDIR:-/tmp}/omnicloud_bench_${points}.las
[ -f "$big" ] || target/release/examples/gen_big_las "$big" "$points"
mkdir -p "$out"

fast=bounds+raycast,quad+sprite
run() { # NAME SCENE STEREO MODES [extra bench options]
  local name=$1 scene=$2 stereo=$3 modes=$4
  shift 4
  local args=(bench "$scene" --width "$width" --stereo "$stereo" --warmup "$warmup"
    --frames "$frames" --out "$out/$name" --quiet "$@")
  [ "$modes" = all ] || args+=(--modes "$modes")
  echo "== $name" >&2
  "$bin" "${args[@]}"
}
run autzen_ods  data/autzen_trim.laz ods  all   --radius 0.4
run autzen_mono data/autzen_trim.laz none all   --radius 0.4
run big_ods     "$big"               ods  $fast
run big_mono    "$big"               none $fast

{
  echo "# GPU benchmark"
  echo
  echo "- date: $(date -u +%Y-%m-%dT%H:%MZ); command: \`tools/gpu_bench.sh\` (WIDTH=$width POINTS=$points FRAMES=$frames WARMUP=$warmup)"
  command -v nvidia-smi >/dev/null && echo "- GPU: $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader | head -1)"
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
} > "$out/summary.md"
cat "$out/summary.md"
