// PageStatus: what the page is doing, for a person (#status's text, #stats) and for scripts
// (#status's data attributes and the document title; tests/tools/viewer_headless.mjs reads
// them): data-state is connecting, loading, ready (rest pose shown), streaming or error;
// data-error the reason; data-figures StreamStats' figures and data-viewports the viewports'
// rectangles on the page, as JSON.
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
    this.stats.textContent = `${figures.fps} fps · round trip p50 ${figures.roundTripP50Ms.toFixed(1)}` +
        ` ms, p99 ${figures.roundTripP99Ms.toFixed(1)} ms · ${(figures.replyBytes / 1024).toFixed(0)} KiB/pose`;
  }
}
