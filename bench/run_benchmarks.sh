#!/usr/bin/env bash
# Runs the Release benchmarks and prints the performance tables of docs/performance.md: deformation in ns per
# vertex (sweep, LBS, DQS) with the sweep/LBS ratio measured in the same run (and the sweep's
# SSE2 loops where the CPU has AVX2), binding time, the daemon, the compact vertex streams,
# the fleet and the Python package.
set -euo pipefail
# Usage: run_benchmarks.sh [build dir] [repetitions]
build=${1:-build/release}
out=$(mktemp -d)
# Each benchmark runs `repetitions` times (default 3) and the table keeps the fastest: the
# machine is shared, and other load only ever adds time.
repetitions=${2:-3}
"$build/bench/deform_bench" --benchmark_format=json --benchmark_min_time=0.3 \
  --benchmark_repetitions="$repetitions" >"$out/deform.json"
"$build/bench/bind_bench" --benchmark_format=json >"$out/bind.json"
/usr/bin/python3 - "$out/deform.json" "$out/bind.json" <<'PY'
import json, sys
rows = {}
for b in json.load(open(sys.argv[1]))["benchmarks"]:
    if b.get("run_type", "iteration") != "iteration":
        continue  # aggregates of the repetitions
    method, model, outputs = b["run_name"].split("/")[:3]
    row = rows.setdefault((model, outputs), {})
    row[method] = min(row.get(method, float("inf")), b["per_vertex"] * 1e9)
    row["vertices"] = int(b["vertices"])
# "sweep" runs the widest vertex loops the CPU has; "sweep_sse2" (present when that is AVX2) the
# x86-64 baseline's, so the table shows both.
sse2 = any("sweep_sse2" in r for r in rows.values())
extra = " sweep SSE2 ns/vertex | SSE2 / LBS | SSE2 ms/pose |" if sse2 else ""
print("| mesh | vertices | outputs | sweep ns/vertex | LBS ns/vertex | DQS ns/vertex | sweep / LBS | sweep ms/pose |" + extra)
print("|---|---|---|---|---|---|---|---|" + ("---|---|---|" if sse2 else ""))
for (model, outputs), r in rows.items():
    line = (f"| {model} | {r['vertices']:,} | {outputs} | {r['sweep']:.1f} | {r['lbs']:.1f} | "
            f"{r['dqs']:.1f} | {r['sweep'] / r['lbs']:.2f} | {r['sweep'] * r['vertices'] / 1e6:.3f} |")
    if sse2:
        line += (f" {r['sweep_sse2']:.1f} | {r['sweep_sse2'] / r['lbs']:.2f} | "
                 f"{r['sweep_sse2'] * r['vertices'] / 1e6:.3f} |")
    print(line)
print()
print("| binding | vertices | ms |")
print("|---|---|---|")
for b in json.load(open(sys.argv[2]))["benchmarks"]:
    print(f"| {b['name']} | {int(b['vertices']):,} | {b['real_time']:.0f} |")
PY
rm -rf "$out"

# The daemon over loopback: round trip, throughput and overhead against in-process deformation.
"$build/bench/server_bench"

# Compact vertex streams: bytes and encode / decode time per pose of PosedVertices' float32,
# float16 and meshopt formats, as ratios against float32 in the same run.
"$build/bench/vertex_stream_bench"

# The fleet: the HAProxy hop on the pose round trip, and renders on one and two replicas.
if command -v haproxy >/dev/null; then
  "$build/bench/fleet_bench"
else
  echo "fleet_bench skipped: haproxy is not installed (deploy/install-deps.sh)"
fi

# The Python package against the C++ client: poses a second received as NumPy arrays.
/usr/bin/python3 "$(dirname "$0")/python_client_bench.py" "$build"
