#!/usr/bin/python3
"""python_client_bench: how many poses a second the Python package (client_examples/python)
receives as NumPy arrays, against the C++ client (stream_poses --flat-out) on the same daemon
and model in the same run (issue 18's target: >= 1,000 poses/s of the 14.5k male).

  bench/python_client_bench.py [BUILD_DIR] [--model M.glb] [--bvh CLIP.bvh] [--poses N]

Installs the package into a temporary venv (offline, as tests/server/python_package_test.cpp
does), starts sweepd from BUILD_DIR on a free port and a Unix socket, uploads the model,
streams N poses with Client.poses, then with AsyncClient.poses (asyncio; the server's
max_poses_in_flight in flight each), then with Client.poses on the Unix socket, plainly and
with the replies in shared memory (protocol 1.10, poses(shared=True)), and then the clip's
first N frames with the C++ client over TCP. Prints one table row per client and the ratios.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def start_daemon(build, directory):
    port_file = os.path.join(directory, "port")
    daemon = subprocess.Popen([os.path.join(build, "server/sweepd"), "--port", "0", "--port-file",
                               port_file, "--store-dir", os.path.join(directory, "store"),
                               "--mannequin-vertices", "1000",
                               "--unix-socket", os.path.join(directory, "sweepd.sock")],
                              stderr=open(os.path.join(directory, "sweepd.log"), "w"))
    deadline = time.monotonic() + 60
    while not os.path.exists(port_file) or not open(port_file).read().strip():
        if daemon.poll() is not None or time.monotonic() > deadline:
            sys.exit(f"sweepd did not start: {open(os.path.join(directory, 'sweepd.log')).read()}")
        time.sleep(0.1)
    return daemon, int(open(port_file).read())


PYTHON_STREAM = """
import asyncio, sys, time
import numpy as np
from sweepd_client import AsyncClient, Client
port, unix, model, count = int(sys.argv[1]), sys.argv[2], sys.argv[3], int(sys.argv[4])
variant = sys.argv[5]

def bent(joints):
    # Distinct small bends per frame, made before the clock starts.
    angles = np.linspace(0.0, 0.6, count, dtype=np.float32)[:, None] * np.ones(joints, np.float32)
    return [np.stack([np.sin(a / 2), np.zeros(joints), np.zeros(joints), np.cos(a / 2)], 1)
            for a in angles]

def blocking(where, shared=False):
    with Client(**where) as sweepd:
        body = sweepd.upload(model)
        frames = bent(len(body.joint_names))
        if shared:  # one slot per pose in flight
            sweepd.map_shared_memory(sweepd.max_poses_in_flight * body.vertex_count * 12)
        sweepd.pose(body)  # warm up the connection and the server's caches
        start = time.perf_counter()
        received = sum(p.positions.shape[0] == body.vertex_count
                       for p in sweepd.poses(body, frames, shared=shared))
        return received, time.perf_counter() - start, body.vertex_count

async def awaited():
    async with AsyncClient("127.0.0.1", port) as sweepd:
        body = await sweepd.upload(model)
        frames = bent(len(body.joint_names))
        await sweepd.pose(body)
        start = time.perf_counter()
        received = 0
        async for p in sweepd.poses(body, frames):
            received += p.positions.shape[0] == body.vertex_count
        return received, time.perf_counter() - start, body.vertex_count

if variant == "async":
    received, seconds, vertices = asyncio.run(awaited())
else:
    where = {"port": port} if variant == "blocking" else {"unix": unix}
    received, seconds, vertices = blocking(where, shared=variant == "shared")
print(f"{received} {seconds} {vertices}")
"""


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build/release"))
    parser.add_argument("--model", default=os.path.join(ROOT, "../shared/data/models/"
                                                        "makehuman_male_cmu.glb"))
    parser.add_argument("--bvh", default=os.path.join(ROOT, "../shared/data/motion/cmu_01_01.bvh"))
    parser.add_argument("--poses", type=int, default=2000)
    options = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="python_client_bench_") as directory:
        venv = os.path.join(directory, "venv")
        subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv],
                       check=True)
        source = os.path.join(directory, "source")
        shutil.copytree(os.path.join(ROOT, "client_examples/python"), source,
                        ignore=shutil.ignore_patterns("build", "*.egg-info"))
        subprocess.run([os.path.join(venv, "bin/pip"), "install", "-q", "--no-index",
                        "--no-build-isolation", source], check=True)
        daemon, port = start_daemon(options.build, directory)
        try:
            rates = {}
            for variant in ("blocking", "async", "unix", "shared"):
                python = subprocess.run([os.path.join(venv, "bin/python"), "-c", PYTHON_STREAM,
                                         str(port), os.path.join(directory, "sweepd.sock"),
                                         options.model, str(options.poses), variant],
                                        check=True, capture_output=True, text=True, cwd=directory)
                received, seconds, vertices = python.stdout.split()
                rates[variant] = int(received) / float(seconds)
            cpp = subprocess.run([os.path.join(options.build, "client_examples/stream_poses"),
                                  "--port", str(port), "--model-file", options.model, "--bvh",
                                  options.bvh, "--frames", str(options.poses), "--flat-out"],
                                 check=True, capture_output=True, text=True)
            cpp_rate = float(re.search(r"poses: .* \((\d+)/s\)", cpp.stdout).group(1))
        finally:
            daemon.terminate()
            daemon.wait()
    print(f"| client | model vertices | poses | poses/s |")
    print(f"|---|---|---|---|")
    print(f"| Python package, Client, NumPy arrays | {int(vertices):,} | {received} | "
          f"{rates['blocking']:.0f} |")
    print(f"| Python package, AsyncClient, NumPy arrays | {int(vertices):,} | {received} | "
          f"{rates['async']:.0f} |")
    print(f"| Python package, Client, Unix socket | {int(vertices):,} | {received} | "
          f"{rates['unix']:.0f} |")
    print(f"| Python package, Client, Unix socket, replies in shared memory | {int(vertices):,} | "
          f"{received} | {rates['shared']:.0f} |")
    print(f"| C++ stream_poses (baseline) | {int(vertices):,} | {options.poses} | {cpp_rate:.0f} |")
    print(f"Python / C++: {rates['blocking'] / cpp_rate:.2f} (Client), "
          f"{rates['async'] / cpp_rate:.2f} (AsyncClient), {rates['unix'] / cpp_rate:.2f} (Unix "
          f"socket), {rates['shared'] / cpp_rate:.2f} (shared memory)")

if __name__ == "__main__":
    main()
