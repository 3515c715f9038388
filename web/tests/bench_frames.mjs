// What the dashboard's benches share (`make bench-web`, docs/dashboard.md "Benchmark"): frames
// counted in the page with requestAnimationFrame, the JS heap after a collection, the
// service's API and the verdict words.
export const MB = 1024 * 1024;
export const GOAL_FPS = 30;

export const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
export const verdict = (met) => (met ? 'met' : 'MISSED');

// Counts frames in the page with requestAnimationFrame: per whole second from the first, so
// that what is kept stays small (10 minutes of timestamps would be 0.3 MB of the heap measured).
export function startFrames(page) {
  return page.evaluate(() => {
    const frames = { first: null, last: null, count: 0, perSecond: [] };
    window.__benchFrames = frames;
    window.__benchCounting = true;
    const tick = (time) => {
      frames.first ??= time;
      frames.last = time;
      frames.count++;
      const second = Math.floor((time - frames.first) / 1000);
      while (frames.perSecond.length <= second) frames.perSecond.push(0);
      frames.perSecond[second]++;
      if (window.__benchCounting) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}

// Mean fps over the whole span and the frames in each whole 1 s window: the fewest, the
// median and how many windows had fewer than GOAL_FPS.
export async function stopFrames(page) {
  const frames = await page.evaluate(() => {
    window.__benchCounting = false;
    return window.__benchFrames;
  });
  if (frames.count < 2) return { mean: 0, min: 0, median: 0, below: 0, windows: 0, frames: frames.count };
  const span = (frames.last - frames.first) / 1000;
  const perSecond = frames.perSecond.slice(0, Math.floor(span));  // the last one is not whole
  const sorted = [...perSecond].sort((a, b) => a - b);
  return {
    mean: (frames.count - 1) / span, min: sorted[0], median: sorted[Math.floor(sorted.length / 2)],
    below: perSecond.filter((count) => count < GOAL_FPS).length, windows: perSecond.length, frames: frames.count,
  };
}

// The page's JS heap in MB after a full collection (CDP; HeapProfiler.enable first).
export async function heapMb(session) {
  await session.send('HeapProfiler.collectGarbage');
  const { usedSize } = await session.send('Runtime.getHeapUsage');
  return usedSize / MB;
}

export async function api(base, route, init) {
  const response = await fetch(new URL(route, base), init);
  const text = await response.text();
  if (!response.ok) throw new Error(`${init?.method ?? 'GET'} ${route}: ${response.status} ${text}`);
  return JSON.parse(text);
}

// The functions with the most self time in a CDP Profiler profile, printed.
export function printProfile(profile, count = 15) {
  const selfTime = new Map();
  const interval = profile.timeDeltas.length ? (profile.endTime - profile.startTime) / profile.timeDeltas.length : 0;
  const byId = new Map(profile.nodes.map((node) => [node.id, node]));
  for (const id of profile.samples) {
    const frame = byId.get(id).callFrame;
    const key = `${frame.functionName || '(anonymous)'} ${frame.url.split('/').pop()}:${frame.lineNumber}:${frame.columnNumber}`;
    selfTime.set(key, (selfTime.get(key) ?? 0) + interval / 1000);
  }
  console.log('  most self time (CDP Profiler):');
  for (const [key, ms] of [...selfTime].sort((a, b) => b[1] - a[1]).slice(0, count)) {
    console.log(`    ${(ms / 1000).toFixed(2)} s  ${key}`);
  }
}
