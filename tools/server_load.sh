#!/usr/bin/env bash
# Load on `omnicloud view` or `omnicloud serve` (loopback only): CLIENTS clients at once for
# SECONDS seconds, a few slowloris clients beside them, with the server's memory sampled.
# The results go into docs/RELIABILITY.md ("Servers under load and abuse").
#
#   tools/server_load.sh view  [SECONDS] [CLIENTS]   # a folder of four 1024x512 noise frames
#   tools/server_load.sh serve [SECONDS] [CLIENTS]   # data/autzen_trim.laz at --width 512
set -euo pipefail
kind=${1:?usage: tools/server_load.sh view|serve [SECONDS] [CLIENTS]}
seconds=${2:-60}
clients=${3:-50}
cd "$(dirname "$0")/.."
# SERVER_LOAD_BIN: a folder with omnicloud and examples/server_load built already.
bin=${SERVER_LOAD_BIN:-}
if [ -z "$bin" ]; then
  cargo build -q --bin omnicloud --example server_load
  bin=${CARGO_TARGET_DIR:-target}/debug
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
case $kind in
  view)
    "$bin/examples/server_load" frames "$work/frames" --count 4 --width 1024
    "$bin/omnicloud" view "$work/frames" --port 0 >"$work/out" 2>&1 &
    ;;
  serve)
    "$bin/omnicloud" serve data/autzen_trim.laz --port 0 --width 512 -q >"$work/out" 2>&1 &
    ;;
  *) echo "view or serve, not $kind" >&2; exit 2 ;;
esac
pid=$!
for _ in $(seq 600); do
  grep -q '^open http://' "$work/out" && break
  kill -0 "$pid" 2>/dev/null || { cat "$work/out" >&2; exit 1; }
  sleep 0.5
done
addr=$(sed -n 's|^open http://\([^/]*\)/.*|\1|p' "$work/out" | head -n1)
echo "$kind $(uname -srm), $(nproc) cores: $bin/omnicloud $kind at $addr, pid $pid"
"$bin/examples/server_load" "$kind" "$addr" --pid "$pid" --clients "$clients" --seconds "$seconds"
kill -INT "$pid"
wait "$pid"
echo "server exited cleanly after the load"
