#!/usr/bin/python3
"""strangers_flood: whether honest clients get in while silent peers flood sweepd from the same
address (issue 49 item 1). FLOODERS processes open loopback connections that never say Hello
as fast as they can (each keeps at most 64 open); meanwhile 100 honest connections, 20 ms
apart, each send Hello and read the reply. Starts its own daemon (no token; 2k mannequin).

    build/release/fuzz/make_seeds build/seeds        # the Hello: the frames seed's first frame
    /usr/bin/python3 bench/strangers_flood.py build/release/server/sweepd build/seeds/frames/seed_0 4

Prints the silent connection rate, how many honest Hellos were answered and admitted (the
daemon's "hello" log lines), their connect-to-reply p50 and max, and the strangers shed.
"""
import multiprocessing, os, shutil, socket, struct, subprocess, sys, tempfile, time, urllib.request

sweepd, seed, flooders = sys.argv[1], sys.argv[2], int(sys.argv[3])
raw = open(seed, "rb").read()[1:]
hello = raw[:4 + struct.unpack("<I", raw[:4])[0]]
d = tempfile.mkdtemp(prefix="strangers_flood_")
proc = subprocess.Popen([sweepd, "--port", "0", "--port-file", d + "/port", "--store-dir", d + "/store",
                         "--mannequin-vertices", "2000", "--position-maps", "0",
                         "--http-listen", "127.0.0.1:0", "--http-port-file", d + "/http"],
                        stdout=subprocess.DEVNULL, stderr=open(d + "/log", "w"))
while not os.path.exists(d + "/port"):
    time.sleep(0.05)
port = int(open(d + "/port").read())
http = int(open(d + "/http").read())
def metric(name):
    page = urllib.request.urlopen(f"http://127.0.0.1:{http}/metrics").read().decode()
    return [l for l in page.splitlines() if l.startswith(name + " ") or l.startswith(name + "{")]
def flood(port, stop, connects):
    held = []
    while not stop.value:
        try:
            held.append(socket.create_connection(("127.0.0.1", port), timeout=2))
            with connects.get_lock():
                connects.value += 1
        except OSError:
            pass
        if len(held) > 64:  # the server has shed the older ones by now
            for s in held[:32]:
                s.close()
            held = held[32:]
stop = multiprocessing.Value("b", False)
connects = multiprocessing.Value("l", 0)
workers = [multiprocessing.Process(target=flood, args=(port, stop, connects)) for _ in range(flooders)]
for w in workers: w.start()
time.sleep(1)
c0, t0 = connects.value, time.perf_counter()
times, answered = [], 0
for i in range(100):
    t = time.perf_counter()
    s = socket.create_connection(("127.0.0.1", port), timeout=10)
    s.sendall(hello)
    head = s.recv(4)
    if len(head) == 4:
        answered += 1
    times.append((time.perf_counter() - t) * 1000)
    s.close()
    time.sleep(0.02)
rate = (connects.value - c0) / (time.perf_counter() - t0)
stop.value = True
for w in workers: w.join()
time.sleep(0.5)
shed = metric("sweepd_strangers_shed_total")
hellos = sum(1 for line in open(d + "/log") if '"event":"hello"' in line)
proc.terminate()
proc.wait()
shutil.rmtree(d)
times.sort()
print(f"{flooders} flooding threads, {rate:.0f} silent connects/s from 127.0.0.1: honest Hellos answered "
      f"{answered}/100, admitted {hellos}/100; connect+Hello+reply p50 {times[50]:.1f} ms, max {times[-1]:.1f} ms; {shed}")
