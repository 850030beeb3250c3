// PageStatus: what the page is doing, for a person (#status's text, #stats) and for scripts
// (#status's data attributes and the document title; tests/tools/viewer_headless.mjs reads
// them): data-state is connecting, loading, ready (rest pose shown), uploading, streaming (the
// clip plays, or a stream's frames arrive), posing (the joint sliders moved) or error;
// data-error the reason; data-figures StreamStats' figures (and, watching a stream, `stream`:
// StreamWatch's figures) and data-viewports the viewports' rectangles on the page, as JSON.
export class PageStatus {
  constructor(statusElement, statsElement) {
    this.element = statusElement;
    this.stats = statsElement;
  }

  set(state, text = state) {
    this.element.dataset.state = state;
    this.element.textContent = text;
    document.title = `sweepd viewer: ${state}`;
  }

  fail(error) {
    this.element.dataset.error = error.message ?? String(error);
    this.set('error', `error: ${this.element.dataset.error}`);
  }

  figures(figures, viewports) {
    this.element.dataset.figures = JSON.stringify(figures);
    this.element.dataset.viewports = JSON.stringify(viewports);
    const { fps, roundTripP50Ms, roundTripP99Ms, replyBytes, stream } = figures;
    // A stream's frames have no round trip: they come when the sender sends.
    const roundTrip = stream ? ''
      : ` · round trip p50 ${roundTripP50Ms.toFixed(1)} ms, p99 ${roundTripP99Ms.toFixed(1)} ms`;
    this.stats.textContent =
        `${fps} fps${roundTrip} · ${(replyBytes / 1024).toFixed(0)} KiB/pose`;
  }
}
