// Benchmark, a figure and not a test (`make bench-web`, docs/dashboard.md "Benchmark"): an
// LS5 at 1 kHz shown live should keep the page at >= 30 frames a second and its heap growth
// under 10 MB, against an idle page's frames in the same run.
import { spawn } from 'node:child_process';
import path from 'node:path';
import { api, GOAL_FPS, heapMb, printProfile, sleep, startFrames, stopFrames, verdict } from './bench_frames.mjs';
import { cli, launch, screenshots, stopped, waitForLine } from './support.mjs';

const SECONDS = Number(process.env.RANGEKIT_BENCH_SECONDS ?? 60);
const BASELINE_S = 10;
const GOAL_HEAP_MB = 10;
const RATE_HZ = 1000;

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
  if (profile) printProfile(profile);
} finally {
  await browser?.close();
  await stopped(serve);
}
