#!/usr/bin/env bash
# Resident memory of a long ODS tour: runs `omnicloud tour` and samples the process's VmRSS
# with the number of finished frames, then reports the RSS when frame 100 was written and the
# largest RSS after it.
#
#   tools/tour_memory.sh [FRAMES] [WIDTH] [SCAN] [OUT_DIR]
#   defaults: 1000 frames, 512 per eye, data/autzen_trim.laz, a temporary folder
#   OMNICLOUD=path/to/omnicloud (default target/release/omnicloud); SAMPLE_S (default 0.5);
#   STEREO (default ods); TOUR_PATH (default data/tours/autzen_loop.csv)
set -euo pipefail
frames=${1:-1000}
width=${2:-512}
scan=${3:-data/autzen_trim.laz}
out=${4:-$(mktemp -d)}
bin=${OMNICLOUD:-target/release/omnicloud}
sample=${SAMPLE_S:-0.5}
path=${TOUR_PATH:-data/tours/autzen_loop.csv}
stereo=${STEREO:-ods}
log="$out.rss.tsv"

"$bin" tour "$scan" --path "$path" -o "$out" --stereo "$stereo" --width "$width" --frames "$frames" -q &
pid=$!
start=$EPOCHREALTIME
echo -e "seconds\tframes\trss_kib" >"$log"
while kill -0 "$pid" 2>/dev/null; do
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  done_frames=$( (find "$out" -maxdepth 1 -name "frame_*.png" 2>/dev/null || true) | wc -l)
  [ -n "$rss" ] && awk -v a="$start" -v b="$EPOCHREALTIME" -v f="$done_frames" -v r="$rss" \
    'BEGIN { printf "%.1f\t%d\t%d\n", b - a, f, r }' >>"$log"
  sleep "$sample"
done
status=0
wait "$pid" || status=$?
awk -v frames="$frames" 'NR > 1 {
    if (!at100 && $2 >= 100) at100 = $3
    if (at100 && $3 > maxafter) maxafter = $3
    if ($3 > peak) peak = $3
    last = $3; secs = $1
  }
  END {
    if (!at100) { print "the tour never reached frame 100"; exit 1 }
    printf "frames %d in %.0f s; RSS at frame 100: %.1f MiB; max after: %.1f MiB (%+.2f %%); at the end: %.1f MiB; peak overall %.1f MiB\n",
      frames, secs, at100 / 1024, maxafter / 1024, (maxafter - at100) * 100 / at100, last / 1024, peak / 1024
    if (maxafter > at100 * 1.05) { print "FAIL: grew by more than 5 %"; exit 1 }
  }' "$log"
echo "samples: $log"
exit "$status"
