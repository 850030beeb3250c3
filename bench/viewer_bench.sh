#!/usr/bin/env bash
# The browser viewer's streaming figures (issue 18's target: 60 fps, p99 round trip <= 5 ms):
# starts sweepd on loopback with the 72k-vertex mannequin (its default model at that size),
# --ws-listen and --http-listen serving the built viewer, loads /viewer in Debian's headless
# Chromium (WebGL on SwiftShader: software, no GPU) through tests/tools/viewer_headless.mjs,
# streams CMU clip 01_01 for SECONDS and prints what the page measured: pose sets drawn per
# second (three poses each: sweep, LBS, DQS) and the round trip of a pose request, p50 and p99.
# METHODS (e.g. sweep) streams and shows only those.
#
# Usage: bench/viewer_bench.sh [build dir] [seconds] [vertices] [methods, default sweep,lbs,dqs]
set -euo pipefail
build=${1:-build/release}
seconds=${2:-20}
vertices=${3:-72000}
methods=${4:-sweep,lbs,dqs}
root=$(cd "$(dirname "$0")/.." && pwd)
clip="$root/../shared/data/motion/cmu_01_01.bvh"
for need in chromium node; do
  command -v "$need" >/dev/null || { echo "viewer_bench: $need is not installed (deploy/install-deps.sh)" >&2; exit 1; }
done
[ -f "$build/client_examples/web/viewer/index.html" ] || { echo "viewer_bench: build the viewer first (target viewer_page)" >&2; exit 1; }
[ -f "$clip" ] || { echo "viewer_bench: no clip $clip" >&2; exit 1; }

work=$(mktemp -d)
"$build/server/sweepd" --port 0 --port-file "$work/port" --store-dir "$work/store" \
  --ws-listen 127.0.0.1:0 --ws-port-file "$work/ws_port" \
  --http-listen 127.0.0.1:0 --http-port-file "$work/http_port" \
  --viewer-dir "$build/client_examples/web/viewer" --token bench \
  --mannequin-vertices "$vertices" --position-maps 0 2>"$work/sweepd.log" >/dev/null &
daemon=$!
trap 'kill $daemon 2>/dev/null; wait $daemon 2>/dev/null; rm -rf "$work"' EXIT
for _ in $(seq 600); do [ -f "$work/port" ] && break; sleep 0.1; done
[ -f "$work/port" ] || { echo "viewer_bench: sweepd did not start:" >&2; cat "$work/sweepd.log" >&2; exit 1; }

url="http://127.0.0.1:$(cat "$work/http_port")/viewer?ws=ws://127.0.0.1:$(cat "$work/ws_port")&token=bench&methods=$methods"
node "$root/tests/tools/viewer_headless.mjs" --url "$url" --bvh "$clip" --frames 1 \
  --seconds "$seconds" --status "$work/status.json" --timeout $((seconds + 120)) >/dev/null
/usr/bin/python3 - "$work/status.json" "$vertices" "$seconds" "$methods" <<'PY'
import json, sys
status, vertices, seconds, methods = json.load(open(sys.argv[1])), int(sys.argv[2]), *sys.argv[3:]
f = status["figures"]
print(f"viewer, {vertices:,}-vertex mannequin, CMU 01_01, {seconds} s in headless Chromium "
      f"(SwiftShader): {f['fpsSinceStart']:.1f} frames/s drawn ({methods}: a pose each), "
      f"round trip p50 {f['roundTripP50Ms']:.1f} ms, p99 {f['roundTripP99Ms']:.1f} ms over "
      f"{f['poses']} poses, {f['replyBytes'] / 1024:.0f} KiB per pose (float16)")
PY
