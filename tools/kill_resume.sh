#!/usr/bin/env bash
# kill -9 at random moments of a tour, resumed each time: after each kill every frame file on
# disk is whole (a PNG ending in its IEND chunk), and the finished folder is byte for byte the
# folder of an uninterrupted run (tour.log aside: one line per frame rendered, with its time).
#
#   tools/kill_resume.sh [FRAMES] [WIDTH] [KILLS] [SEED]
#   defaults: 120 ODS frames, 512 per eye, 5 kills, seed 1; the scan data/autzen_trim.laz
#   along data/tours/autzen_loop.csv, rasterized (RENDERER=raytrace for the ray tracer).
#   OMNICLOUD=path/to/omnicloud (default target/release/omnicloud)
set -euo pipefail
frames=${1:-120}
width=${2:-512}
kills=${3:-5}
seed=${4:-1}
bin=${OMNICLOUD:-target/release/omnicloud}
scan=${SCAN:-data/autzen_trim.laz}
path=${TOUR_PATH:-data/tours/autzen_loop.csv}
renderer=${RENDERER:-raster}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

args=(--path "$path" --stereo ods --width "$width" --frames "$frames" --renderer "$renderer" -q)
tour() { "$bin" tour "$scan" -o "$1" "${args[@]}"; }
count() { (find "$1" -maxdepth 1 -name "frame_*.png" 2>/dev/null || true) | wc -l; }

# Both runs write into the same folder name (tour.json holds it in every frame's command):
# the uninterrupted one first, then moved aside.
start=$EPOCHREALTIME
tour "$work/killed"
mv "$work/killed" "$work/reference"
reference_s=$(awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "%.1f", b - a }')
echo "uninterrupted: $frames frames in $reference_s s"

RANDOM=$seed
for k in $(seq 1 "$kills"); do
  before=$(count "$work/killed")
  # A random moment within the next stretch of the run (the scan loads again each time).
  delay=$(awk -v r=$RANDOM -v t="$reference_s" -v k="$kills" \
    'BEGIN { printf "%.2f", 1 + r / 32768 * t / k }')
  # The binary itself in the background, so that $! is its process, not a subshell's.
  "$bin" tour "$scan" -o "$work/killed" "${args[@]}" &
  pid=$!
  sleep "$delay"
  if ! kill -0 "$pid" 2>/dev/null; then
    echo "kill $k: the tour had already finished"; exit 1
  fi
  kill -9 "$pid"
  wait "$pid" 2>/dev/null || true
  after=$(count "$work/killed")
  temps=$( (find "$work/killed" -maxdepth 1 -name '.*.tmp' 2>/dev/null || true) | wc -l)
  for f in "$work/killed"/frame_*.png; do
    [ -e "$f" ] || continue
    if [ "$(tail -c 8 "$f" | od -An -tx1 | tr -d ' \n')" != "49454e44ae426082" ]; then
      echo "kill $k: $f is not a whole PNG"; exit 1
    fi
  done
  echo "kill -9 #$k after $delay s: frames $before -> $after, every one whole; $temps temporary file(s) left"
done
tour "$work/killed"
echo "resumed to the end: $(count "$work/killed") frames"
if diff -r -x tour.log "$work/reference" "$work/killed" >/dev/null; then
  echo "PASS: the finished folder is byte-identical to the uninterrupted run's ($(ls "$work/killed" | wc -l) files; tour.log aside)"
else
  diff -r -x tour.log -q "$work/reference" "$work/killed" | head
  echo "FAIL: the folders differ"; exit 1
fi
