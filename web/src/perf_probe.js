// Performance, read by tests and bench_render.mjs: when the map first appeared on screen, and the longest
// main-thread part of a tile update (decoding itself runs in DRACOLoader's workers).

/** The page's performance record, kept up to date from `view`'s frames and the browser's long tasks. */
export function createPerfProbe(view) {
  const perf = {
    helloMs: null, // when the server's hello arrived (ms since the page started loading)
    firstTileFrameMs: null, // when the first tile frame arrived
    firstTileDecodedMs: null, // when the first tile came back from the decoder
    firstMapRenderMs: null, // when the first frame with map patches in it was drawn
    maxTileMainThreadMs: 0, // the longest main-thread part of one tile update
    tileUpdates: 0,
    slowTileUpdates: [], // tile updates whose main-thread part took over 16 ms: { n (which update), ms, patches }
    longTasks: [], // durations of main-thread tasks over 50 ms (PerformanceObserver 'longtask')
    renderMs: [], // the last 120 frames' render() durations on the main thread
  };
  try {
    new PerformanceObserver((list) => {
      for (const entry of list.getEntries()) perf.longTasks.push(Math.round(entry.duration));
    }).observe({ type: 'longtask', buffered: true });
  } catch {
    // longtask is a Chromium feature; other browsers just do without the measurement
  }
  view.onFrame = (ms) => {
    perf.renderMs.push(Math.round(ms * 10) / 10);
    if (perf.renderMs.length > 120) perf.renderMs.shift();
    if (perf.firstMapRenderMs === null && view.tiles.drawnCount > 0) perf.firstMapRenderMs = performance.now();
  };
  return perf;
}
