#!/usr/bin/python3
"""side_port_probes: how long sweepd's HTTP side port takes to answer /readyz (connect to the
answer's end, 200 requests each) alone, beside 256 peers sending a request head one byte every
100 ms and reconnecting when cut (slowloris; issue 49 item 3), and beside those plus 8 /metrics
scrapers in a loop. Starts its own daemon on loopback (2k mannequin, no position maps).

    /usr/bin/python3 bench/side_port_probes.py build/release/server/sweepd

Prints one line per scene: answers that were not 200, p50, p99 and max in ms. Wall time on
whatever else the machine runs: say the load beside the figures.
"""
import os, shutil, socket, subprocess, sys, tempfile, threading, time

sweepd = sys.argv[1]
d = tempfile.mkdtemp(prefix="strangers_lat_")
proc = subprocess.Popen([sweepd, "--port", "0", "--port-file", d + "/port", "--http-listen",
                         "127.0.0.1:0", "--http-port-file", d + "/http", "--store-dir", d + "/store",
                         "--mannequin-vertices", "2000", "--position-maps", "0"],
                        stdout=subprocess.DEVNULL, stderr=open(d + "/log", "w"))
while not os.path.exists(d + "/port"):
    time.sleep(0.05)
port = int(open(d + "/http").read())

def get(path):
    t = time.perf_counter()
    s = socket.create_connection(("127.0.0.1", port), timeout=10)
    s.sendall(f"GET {path} HTTP/1.1\r\nHost: x\r\n\r\n".encode())
    data = b""
    while True:
        chunk = s.recv(65536)
        if not chunk:
            break
        data += chunk
    s.close()
    return (time.perf_counter() - t) * 1000, data.split(b" ", 2)[1] if data else b"000"

while get("/readyz")[1] != b"200":
    time.sleep(0.05)

def measure(label, n=200):
    times, bad = [], 0
    for _ in range(n):
        ms, status = get("/readyz")
        times.append(ms)
        bad += status != b"200"
    times.sort()
    print(f"{label}: {n} /readyz, not 200: {bad}, p50 {times[n//2]:.2f} ms, p99 {times[int(n*0.99)-1]:.2f} ms, max {times[-1]:.2f} ms", flush=True)

measure("alone")
stop = False
def slow_peers(count):
    peers = []
    while not stop:
        while len(peers) < count and not stop:
            try:
                s = socket.create_connection(("127.0.0.1", port), timeout=1)
                s.sendall(b"GET /metrics HTTP/1.1\r\n")
                peers.append(s)
            except OSError:
                pass
        for s in list(peers):
            try:
                s.send(b"X")
            except OSError:
                peers.remove(s)
                s.close()
        time.sleep(0.1)
    for s in peers:
        s.close()
t = threading.Thread(target=slow_peers, args=(256,)); t.start()
time.sleep(2)
measure("beside 256 slow-header peers (reconnecting when cut)")
def scraper():
    while not stop:
        get("/metrics")
scrapers = [threading.Thread(target=scraper) for _ in range(8)]
for s in scrapers: s.start()
time.sleep(1)
measure("beside 256 slow-header peers and 8 /metrics scrapers in a loop")
stop = True
t.join()
for s in scrapers: s.join()
proc.terminate()
proc.wait()
shutil.rmtree(d)
print("load average", os.getloadavg())
