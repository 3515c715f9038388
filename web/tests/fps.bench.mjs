// Benchmark, a figure and not a test (`make bench-web`, docs/dashboard.md "Benchmark"): an
// LS5 at 1 kHz shown live should keep the page at >= 30 frames a second and its heap growth
// under 10 MB, against an idle page's frames in the same run.
import { spawn } from 'node:child_process';
import path from 'node:path';
import { cli, launch, screenshots, stopped, waitForLine } from './support.mjs';

const SECONDS = Number(process.env.RANGEKIT_BENCH_SECONDS ?? 60);
const BASELINE_S = 10;
const GOAL_FPS = 30;
const GOAL_HEAP_MB = 10;
const RATE_HZ = 1000;
const MB = 1024 * 1024;

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

// Counts frames in the page: one timestamp per requestAnimationFrame callback.
function startFrames(page) {
  return page.evaluate(() => {
    const frames = [];
    window.__benchFrames = frames;
    window.__benchCounting = true;
    const tick = (time) => {
      frames.push(time);
      if (window.__benchCounting) requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}

// Mean fps over the whole span and the fewest frames in any whole 1 s window.
async function stopFrames(page) {
  const frames = await page.evaluate(() => {
    window.__benchCounting = false;
    return window.__benchFrames;
  });
  if (frames.length < 2) return { mean: 0, min: 0, frames: frames.length };
  const first = frames[0];
  const span = (frames[frames.length - 1] - first) / 1000;
  const perSecond = new Array(Math.floor(span)).fill(0);
  for (const time of frames) {
    const index = Math.floor((time - first) / 1000);
    if (index < perSecond.length) perSecond[index]++;
  }
  const sorted = [...perSecond].sort((a, b) => a - b);
  return {
    mean: (frames.length - 1) / span, min: sorted[0], median: sorted[Math.floor(sorted.length / 2)],
    below: perSecond.filter((count) => count < GOAL_FPS).length, windows: perSecond.length, frames: frames.length,
  };
}

async function heapMb(session) {
  await session.send('HeapProfiler.collectGarbage');
  const { usedSize } = await session.send('Runtime.getHeapUsage');
  return usedSize / MB;
}

async function api(base, route, init) {
  const response = await fetch(new URL(route, base), init);
  const text = await response.text();
  if (!response.ok) throw new Error(`${init?.method ?? 'GET'} ${route}: ${response.status} ${text}`);
  return JSON.parse(text);
}

const verdict = (met) => (met ? 'met' : 'MISSED');

const serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
serve.stdout.setEncoding('utf8');
let browser;
try {
  const url = await waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  serve.stdout.resume();
  await api(url, '/api/sensors/belt/settings', {
    method: 'PATCH', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ 'period-ms': 1000 / RATE_HZ, thinning: 1, 'result-type': 'pure' }),
  });
  let rate = 0;
  for (let tries = 0; tries < 100 && rate < RATE_HZ * 0.9; ++tries) {
    await sleep(200);
    rate = (await api(url, '/api/sensors/belt')).health.rate_hz;
  }
  if (rate < RATE_HZ * 0.9) throw new Error(`belt streams ${rate.toFixed(1)}/s, not ${RATE_HZ}`);

  browser = await launch();
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  const session = await page.context().newCDPSession(page);
  await session.send('HeapProfiler.enable');

  await page.setContent('<!doctype html><title>idle</title><p>idle page: the frame rate baseline</p>');
  await startFrames(page);
  await sleep(BASELINE_S * 1000);
  const idle = await stopFrames(page);

  await page.goto(`${url}#/sensor/belt`);
  await page.waitForFunction(() => Number(document.querySelector('.live-plot')?.dataset.points ?? 0) >= 1000, null,
    { timeout: 60_000, polling: 100 });
  const profiling = process.env.RANGEKIT_BENCH_PROFILE === '1';
  if (profiling) {
    await session.send('Profiler.enable');
    await session.send('Profiler.start');
  }
  const heapBefore = await heapMb(session);
  const pointsBefore = await page.evaluate(() => Number(document.querySelector('.live-plot').dataset.points));
  await startFrames(page);
  const started = Date.now();
  await sleep(SECONDS * 1000);
  const shown = await stopFrames(page);
  const elapsed = (Date.now() - started) / 1000;
  const pointsAfter = await page.evaluate(() => Number(document.querySelector('.live-plot').dataset.points));
  await page.screenshot({ path: path.join(screenshots, 'fps-bench-ls5.png') });
  const profile = profiling ? (await session.send('Profiler.stop')).profile : null;
  const heapAfter = await heapMb(session);
  const growth = heapAfter - heapBefore;

  console.log(`LS5 live plot, belt at ${rate.toFixed(0)} results/s, ${SECONDS} s on #/sensor/belt (headless chromium):`);
  console.log(`  samples reaching the plot: ${((pointsAfter - pointsBefore) / elapsed).toFixed(0)}/s`);
  console.log(`  frames: mean ${shown.mean.toFixed(1)} fps, median 1 s ${shown.median}, slowest 1 s ${shown.min} fps, ` +
    `${shown.below} of ${shown.windows} seconds under ${GOAL_FPS} (goal >= ${GOAL_FPS} every second: ` +
    `${verdict(shown.min >= GOAL_FPS)}; mean: ${verdict(shown.mean >= GOAL_FPS)})`);
  console.log(`  baseline, idle page for ${BASELINE_S} s: mean ${idle.mean.toFixed(1)} fps, median 1 s ${idle.median}, ` +
    `slowest 1 s ${idle.min} fps, ${idle.below} of ${idle.windows} seconds under ${GOAL_FPS}; ` +
    `ratio of the means ${(shown.mean / idle.mean).toFixed(2)}`);
  console.log(`  JS heap after GC: ${heapBefore.toFixed(1)} MB -> ${heapAfter.toFixed(1)} MB, growth ` +
    `${growth.toFixed(1)} MB (goal < ${GOAL_HEAP_MB} MB: ${verdict(growth < GOAL_HEAP_MB)})`);
  if (profile) {
    const selfTime = new Map();
    const interval = profile.timeDeltas.length ? (profile.endTime - profile.startTime) / profile.timeDeltas.length : 0;
    const byId = new Map(profile.nodes.map((node) => [node.id, node]));
    for (const id of profile.samples) {
      const frame = byId.get(id).callFrame;
      const key = `${frame.functionName || '(anonymous)'} ${frame.url.split('/').pop()}:${frame.lineNumber}:${frame.columnNumber}`;
      selfTime.set(key, (selfTime.get(key) ?? 0) + interval / 1000);
    }
    console.log('  most self time (CDP Profiler):');
    for (const [key, ms] of [...selfTime].sort((a, b) => b[1] - a[1]).slice(0, 15)) {
      console.log(`    ${(ms / 1000).toFixed(2)} s  ${key}`);
    }
  }
} finally {
  await browser?.close();
  await stopped(serve);
}
