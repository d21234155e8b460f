#!/bin/sh
# Runs one fuzz target from its committed seeds plus its earlier runs, nice'd, on one core.
# Usage: run_target.sh TARGET RUNS MAX_SECONDS MAX_LEN
# Findings go to artifacts/TARGET/, new inputs to runs/TARGET/, the log to runs/TARGET.log.
set -eu
cd "$(dirname "$0")"
t=$1 runs=$2 secs=$3 len=$4
B=${CARGO_TARGET_DIR:-target}/x86_64-unknown-linux-gnu/release
mkdir -p "runs/$t" "artifacts/$t"
nice -n 10 "$B/$t" "runs/$t" "corpus/$t" \
    -runs="$runs" -max_total_time="$secs" -max_len="$len" \
    -rss_limit_mb=2048 -malloc_limit_mb=1024 -timeout=20 \
    -artifact_prefix="artifacts/$t/" -print_final_stats=1 > "runs/$t.log" 2>&1 || true
tail -n 14 "runs/$t.log"
