#!/usr/bin/env bash
# Runs the Release benchmarks and prints the performance tables of docs/performance.md: deformation in ns per
# vertex (sweep, LBS, DQS) with the sweep/LBS and DQS/LBS ratios measured in the same run (and
# the SSE2 loops where the CPU has AVX2), stamped with commit, date, CPU and its flags; binding time, the daemon, the compact vertex streams,
# the fleet and the Python package.
set -euo pipefail
# Usage: run_benchmarks.sh [build dir] [repetitions]
build=${1:-build/release}
out=$(mktemp -d)
# Each benchmark runs `repetitions` times (default 3) and the table keeps the fastest: the
# machine is shared, and other load only ever adds time.
repetitions=${2:-3}
# What the figures were measured on: they mean little without it.
flags=$(grep -m1 '^flags' /proc/cpuinfo | tr ' ' '\n' | grep -xE 'sse4_2|avx|avx2|fma|avx512f' | tr '\n' ' ' || true)
echo "Measured $(date -u '+%Y-%m-%d %H:%M UTC') at commit $(git -C "$(dirname "$0")" rev-parse --short HEAD 2>/dev/null || echo unknown)" \
  "on $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) cores, flags: ${flags:-none of sse4_2 avx avx2 fma avx512f}," \
  "load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo
"$build/bench/deform_bench" --benchmark_format=json --benchmark_min_time=0.3 \
  --benchmark_repetitions="$repetitions" >"$out/deform.json"
"$build/bench/bind_bench" --benchmark_format=json >"$out/bind.json"
/usr/bin/python3 - "$out/deform.json" "$out/bind.json" <<'PY'
import json, sys
rows, split, stages = {}, {}, {}
for b in json.load(open(sys.argv[1]))["benchmarks"]:
    if b.get("run_type", "iteration") != "iteration":
        continue  # aggregates of the repetitions
    method, model, outputs = b["run_name"].split("/")[:3]
    if method == "split":  # one pose over threads: wall milliseconds
        key = (model, outputs, int(b["run_name"].split("threads:")[1].split("/")[0]))
        split[key] = min(split.get(key, float("inf")), b["real_time"] / 1e3)
        continue
    if method == "sweep_stage":  # posing or vertices alone: ns per vertex
        key = (model, outputs)
        stages[key] = min(stages.get(key, float("inf")), b["per_vertex"] * 1e9)
        continue
    row = rows.setdefault((model, outputs), {})
    row[method] = min(row.get(method, float("inf")), b["per_vertex"] * 1e9)
    row["vertices"] = int(b["vertices"])
# "sweep", "lbs", "dqs" run the widest vertex loops the CPU has; "…_sse2" (present when that is
# AVX2) the x86-64 baseline's on the same data, each set compared with its own LBS.
sets = [("", "")] + ([("_sse2", "SSE2 ")] if any("sweep_sse2" in r for r in rows.values()) else [])
head = "| mesh | vertices | outputs |"
for _, label in sets:
    head += (f" {label}sweep ns/vertex | {label}LBS ns/vertex | {label}DQS ns/vertex |"
             f" {label}sweep / LBS | {label}DQS / LBS | {label}sweep ms/pose |")
print(head)
print("|---|---|---|" + "---|---|---|---|---|---|" * len(sets))
for (model, outputs), r in rows.items():
    line = f"| {model} | {r['vertices']:,} | {outputs} |"
    for suffix, _ in sets:
        sweep, lbs, dqs = r["sweep" + suffix], r["lbs" + suffix], r["dqs" + suffix]
        line += (f" {sweep:.1f} | {lbs:.1f} | {dqs:.1f} | {sweep / lbs:.2f} | {dqs / lbs:.2f} |"
                 f" {sweep * r['vertices'] / 1e6:.3f} |")
    print(line)
print()
print("| where a sweep pose goes | posing ns/vertex (per frame: keys, curves, table) | vertices ns/vertex |"
      " normals ns/vertex (recomputed from the posed triangles) |")
print("|---|---|---|---|")
for model in dict.fromkeys(m for m, _ in stages):
    print(f"| {model} | {stages[(model, 'posing')]:.2f} | {stages[(model, 'vertices')]:.2f} |"
          f" {stages[(model, 'normals')]:.2f} |")
print()
print("| one pose over threads (sweep) | outputs | threads | ms per pose (wall) | against 1 thread |")
print("|---|---|---|---|---|")
for (model, outputs, threads), ms in sorted(split.items()):
    print(f"| {model} | {outputs} | {threads} | {ms:.2f} | {ms / split[(model, outputs, 1)]:.2f} |")
print()
# bind alone and bind + self-check + adaptation (as sweepctl binds): CPU time of the process
# (both threads), wall time, and the checked bind against bind alone in the same run.
print("| binding | vertices | CPU ms | wall ms | CPU against bind alone |")
print("|---|---|---|---|---|")
bind_rows = [b for b in json.load(open(sys.argv[2]))["benchmarks"]
             if b.get("run_type", "iteration") == "iteration"]
alone = {b["name"].split("/")[1]: b["cpu_time"] for b in bind_rows if b["name"].startswith("bind/")}
for b in bind_rows:
    kind, model = b["name"].split("/")[:2]
    print(f"| {kind}/{model} | {int(b['vertices']):,} | {b['cpu_time']:.0f} | {b['real_time']:.0f} |"
          f" {b['cpu_time'] / alone[model]:.2f} |")
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
