// ClipPlayer: which frame of the clip to show. Paused: the frame slider's. Playing: the frame the
// clip's own clock has reached since play began (frames are skipped when poses come slower
// than the clip's rate), wrapping at the end. Times are performance.now() milliseconds.
export class ClipPlayer {
  constructor() {
    this.frameCount = 0;
    this.framesPerSecond = 0;
    this.playing = false;
    this.startFrame = 0;
    this.startTime = 0;
  }

  load(frameCount, framesPerSecond) {
    this.frameCount = frameCount;
    this.framesPerSecond = framesPerSecond;
    this.playing = false;
    this.startFrame = 0;
  }

  frameAt(now) {
    if (!this.playing || this.frameCount === 0) return this.startFrame;
    const elapsed = Math.floor(((now - this.startTime) * this.framesPerSecond) / 1000);
    return (this.startFrame + elapsed) % this.frameCount;
  }

  play(now) {
    this.startTime = now;
    this.playing = true;
  }

  pause(now) {
    this.startFrame = this.frameAt(now);
    this.playing = false;
  }

  seek(frame, now) {
    this.startFrame = frame;
    this.startTime = now;
  }
}
