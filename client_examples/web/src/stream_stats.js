// StreamStats: the streaming figures the page shows and the benchmark reads. Frame rate: pose
// sets drawn per second, over the last second and since the first; round trip: a pose request
// sent to its reply received (performance.now()), p50 and p99 over the last kWindow poses;
// bytes: the last reply's size (frameReceived: a stream's frame, which has no round trip).
// reset() starts again (a new clip).
const kWindow = 10000;

function percentile(sorted, q) {
  return sorted.length ? sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))] : 0;
}

export class StreamStats {
  constructor() {
    this.reset();
  }

  reset() {
    this.frames = 0;
    this.firstFrameTime = 0;
    this.recentFrameTimes = [];
    this.roundTrips = [];
    this.replyBytes = 0;
  }

  roundTrip(milliseconds, bytes) {
    if (this.roundTrips.length === kWindow) this.roundTrips.shift();
    this.roundTrips.push(milliseconds);
    this.replyBytes = bytes;
  }

  frameReceived(bytes) {
    this.replyBytes = bytes;
  }

  frameDrawn(now) {
    if (this.frames++ === 0) this.firstFrameTime = now;
    this.recentFrameTimes.push(now);
    while (this.recentFrameTimes[0] < now - 1000) this.recentFrameTimes.shift();
  }

  figures(now) {
    const sorted = [...this.roundTrips].sort((a, b) => a - b);
    const elapsed = (now - this.firstFrameTime) / 1000;
    return {
      frames: this.frames,
      fps: this.recentFrameTimes.filter((t) => t > now - 1000).length,
      fpsSinceStart: this.frames > 1 && elapsed > 0 ? (this.frames - 1) / elapsed : 0,
      roundTripP50Ms: percentile(sorted, 0.5),
      roundTripP99Ms: percentile(sorted, 0.99),
      poses: this.roundTrips.length,
      replyBytes: this.replyBytes,
    };
  }
}
