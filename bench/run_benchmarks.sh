#!/usr/bin/env bash
# Runs the Release benchmarks and prints the README's performance tables: deformation in ns per
# vertex (sweep, LBS, DQS) with the sweep/LBS ratio measured in the same run, and binding time.
set -euo pipefail
build=${1:-build/release}
out=$(mktemp -d)
"$build/bench/deform_bench" --benchmark_format=json --benchmark_min_time=0.3 >"$out/deform.json"
"$build/bench/bind_bench" --benchmark_format=json >"$out/bind.json"
/usr/bin/python3 - "$out/deform.json" "$out/bind.json" <<'PY'
import json, sys
rows = {}
for b in json.load(open(sys.argv[1]))["benchmarks"]:
    method, model, outputs = b["name"].split("/")[:3]
    rows.setdefault((model, outputs), {})[method] = b["per_vertex"] * 1e9
    rows[(model, outputs)]["vertices"] = int(b["vertices"])
print("| mesh | vertices | outputs | sweep ns/vertex | LBS ns/vertex | DQS ns/vertex | sweep / LBS | sweep ms/pose |")
print("|---|---|---|---|---|---|---|---|")
for (model, outputs), r in rows.items():
    print(f"| {model} | {r['vertices']:,} | {outputs} | {r['sweep']:.1f} | {r['lbs']:.1f} | "
          f"{r['dqs']:.1f} | {r['sweep'] / r['lbs']:.2f} | {r['sweep'] * r['vertices'] / 1e6:.3f} |")
print()
print("| binding | vertices | ms |")
print("|---|---|---|")
for b in json.load(open(sys.argv[2]))["benchmarks"]:
    print(f"| {b['name']} | {int(b['vertices']):,} | {b['real_time']:.0f} |")
PY
rm -rf "$out"

# The daemon over loopback: round trip, throughput and overhead against in-process deformation.
"$build/bench/server_bench"
