#!/usr/bin/env bash
# The main job: start the sweepd daemon on its default model (the procedural mannequin), stream
# a CMU motion clip to it with the stream_poses client, print the latency figures, have the daemon
# render one EXR position map (render_frames), write a PNG preview of its bound model, and stop
# the daemon.
set -euo pipefail
build=${1:-build/release}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
out=out/demo
rm -rf "$out"
mkdir -p "$out"
clip=../shared/data/motion/cmu_01_01.bvh
token=demo-token

echo "== 1. start sweepd (default model: the procedural mannequin, bound at start-up)"
"$build/server/sweepd" --port 0 --port-file "$out/port" --store-dir "$out/store" \
  --token "$token" 2>"$out/sweepd.log" &
daemon=$!
trap 'kill -TERM $daemon 2>/dev/null || true' EXIT
for _ in $(seq 100); do [ -s "$out/port" ] && break; sleep 0.1; done
[ -s "$out/port" ] || { echo "sweepd did not start; its log:"; cat "$out/sweepd.log"; exit 1; }
port=$(cat "$out/port")
echo "sweepd listening on 127.0.0.1:$port"

if [ ! -f "$clip" ]; then
  echo "(no $clip: ../shared/data is not beside this checkout, nothing to stream)"
else
  echo
  echo "== 2. stream 240 frames of cmu_01_01 at the clip's 120 fps (stream_poses)"
  "$build/client_examples/stream_poses" --port "$port" --token "$token" --bvh "$clip" --frames 240

  echo
  echo "== 3. frame 600 through the daemon: EXR position map (render_frames), PNG preview (sweepctl)"
  "$build/client_examples/render_frames" --server "127.0.0.1:$port" --token "$token" --bvh "$clip" \
    --frames 600-600 --normals -o "$out"
  binding=$(ls "$out"/store/*.sweepbind | head -n 1)
  "$build/cli/sweepctl" render "$binding" --bvh "$clip" --frame 600 --png "$out/frame600.png" --size 600
fi

echo
echo "== 4. stop sweepd (SIGTERM: finishes in-flight work, says Bye, exits 0)"
kill -TERM "$daemon"
wait "$daemon"
trap - EXIT
tail -n 2 "$out/sweepd.log"
echo
echo "demo done: outputs in $out/"
