// Benchmark, a figure and not a test (`make bench-web`, docs/dashboard.md "Benchmark"): the
// overview at a site's size, 100 sensors, should keep >= 30 frames every second for 10
// minutes with a flat heap (the end within 10 % of the start), and answer a keystroke in the
// filter or the problem-only checkbox in under 100 ms. Baselines in the same run: an idle page
// under the same load, and the demo's overview of seven sensors.
import { spawn } from 'node:child_process';
import dgram from 'node:dgram';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { loadavg, tmpdir } from 'node:os';
import path from 'node:path';
import { api, GOAL_FPS, heapMb, printProfile, sleep, startFrames, stopFrames, verdict } from './bench_frames.mjs';
import { percentiles, pressKeys, watchKeystrokes } from './keystrokes.mjs';
import { cli, launch, screenshots, stopped, waitForLine } from './support.mjs';

const SECONDS = Number(process.env.RANGEKIT_SITE_BENCH_SECONDS ?? 600);
const WARMUP_S = Number(process.env.RANGEKIT_SITE_BENCH_WARMUP ?? 70);  // the sparklines' 60 s window filled
const HEAP_EVERY_S = 60;
const BASELINE_S = 20;
const UDP_SENSORS = 96;  // fed by the pacer at 1 kHz each
const ABSENT = 4;        // LS5s on serial ports that do not exist: disconnected, the problem-only view's
const RATE_HZ = 1000;
const KEY_ROUNDS = 4;    // 4 x (6 typed + 6 Backspace + 2 Space) = 56 keystrokes
const GOAL_KEY_MS = 100;
const GOAL_HEAP_RATIO = 0.10;
const pacerPath = process.env.RANGEKIT_UDP_PACER;
if (!pacerPath) throw new Error('RANGEKIT_UDP_PACER names build/rangekit_udp_pacer (make bench-web sets it)');

// A first port with `count` free loopback UDP ports from it.
async function freeUdpPorts(count) {
  for (let attempt = 0; attempt < 20; attempt++) {
    const first = 20000 + Math.floor(Math.random() * 40000);
    const sockets = [];
    try {
      for (let i = 0; i < count; i++) {
        const socket = dgram.createSocket('udp4');
        sockets.push(socket);
        await new Promise((resolve, reject) => {
          socket.once('error', reject);
          socket.bind(first + i, '127.0.0.1', resolve);
        });
      }
      return first;
    } catch {
      // taken: another range
    } finally {
      for (const socket of sockets) socket.close();
    }
  }
  throw new Error(`no ${count} free UDP ports in a row`);
}

function siteFile(firstPort) {
  let site = '';
  for (let i = 0; i < UDP_SENSORS; i++) {
    const name = `udp-${String(i).padStart(2, '0')}`;
    site += `[[sensor]]\nname = "${name}"\nfamily = "ls5"\nudp = "127.0.0.1:${firstPort + i}"\n`;
  }
  for (let i = 1; i <= ABSENT; i++) {
    site += `[[sensor]]\nname = "absent-${i}"\nfamily = "ls5"\nport = "/dev/rangekit-bench-absent-${i}"\n`;
  }
  return site;
}

// CPU seconds (user + system) of a process so far.
function cpuSeconds(pid) {
  const fields = readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
  return (Number(fields[11]) + Number(fields[12])) / 100;  // utime, stime in clock ticks (USER_HZ 100)
}

// The service's count of stream clients it cut off for falling behind (docs/api.md).
async function cutOff(base) {
  const text = await (await fetch(new URL('/metrics', base))).text();
  return Number(text.match(/^rangekit_http_streams_cut_off_total (\d+)/m)?.[1] ?? NaN);
}

async function serveOn(args) {
  const serve = spawn(cli, ['serve', ...args, '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const url = await waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  serve.stdout.resume();
  return { serve, url };
}

async function openOverview(page, url, sensors) {
  await page.goto(url);
  await page.waitForFunction((count) => {
    const cards = [...document.querySelectorAll('.card')];
    return cards.length === count && cards.filter((card) => card.dataset.reading === 'live').length >= Math.min(count, 7);
  }, sensors, { timeout: 120_000, polling: 200 });
  await watchKeystrokes(page);
}

const fps = (frames) => `mean ${frames.mean.toFixed(1)} fps, slowest second ${frames.min}, ${frames.below} of ` +
  `${frames.windows} seconds under ${GOAL_FPS}`;
const keys = (ms) => `p50 ${ms.p50.toFixed(1)} ms, p99 ${ms.p99.toFixed(1)} ms, max ${ms.max.toFixed(1)} ms (${ms.count} keys)`;

const dir = mkdtempSync(path.join(tmpdir(), 'rangekit-site-bench-'));
const children = [];
let browser;
try {
  browser = await launch();
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  const session = await page.context().newCDPSession(page);
  await session.send('HeapProfiler.enable');

  // Baseline: the demo's seven sensors on the same overview.
  const demo = await serveOn(['--demo']);
  children.push(demo.serve);
  await openOverview(page, demo.url, 7);
  await sleep(5000);
  await startFrames(page);
  await sleep(BASELINE_S * 1000);
  const demoFrames = await stopFrames(page);
  const demoKeys = await pressKeys(page, 'bay-c', 1);
  await page.goto('about:blank');
  await stopped(demo.serve);

  // The site: 96 UDP sensors fed by the pacer and 4 on absent ports.
  const firstPort = await freeUdpPorts(UDP_SENSORS);
  writeFileSync(path.join(dir, 'site.toml'), siteFile(firstPort));
  const pacer = spawn(pacerPath, ['--first-port', String(firstPort), '--sensors', String(UDP_SENSORS),
    '--rate-hz', String(RATE_HZ)], { stdio: ['ignore', 'ignore', 'inherit'] });
  children.push(pacer);
  const site = await serveOn(['--config', path.join(dir, 'site.toml')]);
  children.push(site.serve);
  let fed = 0;
  for (let tries = 0; tries < 150 && fed < UDP_SENSORS; ++tries) {
    await sleep(200);
    fed = (await api(site.url, '/api/sensors')).sensors.filter((sensor) => sensor.health.rate_hz >= RATE_HZ * 0.9).length;
  }
  if (fed < UDP_SENSORS) throw new Error(`${fed} of ${UDP_SENSORS} UDP sensors at ${RATE_HZ}/s`);

  // Baseline: an idle page in the same browser, under the same load (pacer and service).
  await page.setContent('<!doctype html><title>idle</title><p>idle page: the frame rate baseline</p>');
  await startFrames(page);
  await sleep(BASELINE_S * 1000);
  const idle = await stopFrames(page);

  await openOverview(page, site.url, UDP_SENSORS + ABSENT);
  await sleep(WARMUP_S * 1000);
  const profiling = process.env.RANGEKIT_BENCH_PROFILE === '1';
  if (profiling) {
    await session.send('Profiler.enable');
    await session.send('Profiler.start');
  }
  const load = [loadavg()[0]];
  const heap = [await heapMb(session)];
  const cpuBefore = cpuSeconds(site.serve.pid);
  const cutBefore = await cutOff(site.url);
  await startFrames(page);
  const started = Date.now();
  for (let at = HEAP_EVERY_S; at <= SECONDS; at += HEAP_EVERY_S) {
    await sleep(started + at * 1000 - Date.now());
    heap.push(await heapMb(session));
    load.push(loadavg()[0]);
  }
  await sleep(started + SECONDS * 1000 - Date.now());
  const shown = await stopFrames(page);
  const elapsed = (Date.now() - started) / 1000;
  const serviceCpu = (cpuSeconds(site.serve.pid) - cpuBefore) / elapsed;
  const cuts = (await cutOff(site.url)) - cutBefore;
  const profile = profiling ? (await session.send('Profiler.stop')).profile : null;
  if (SECONDS % HEAP_EVERY_S !== 0) heap.push(await heapMb(session));
  const { sensors } = await api(site.url, '/api/sensors');
  const served = sensors.reduce((sum, sensor) => sum + sensor.health.rate_hz, 0);
  await page.screenshot({ path: path.join(screenshots, 'site-bench-overview.png') });

  const siteKeys = await pressKeys(page, 'udp-40', KEY_ROUNDS);
  await page.click('#problems');
  await page.screenshot({ path: path.join(screenshots, 'site-bench-problems.png') });

  const filterMs = percentiles(siteKeys.filterMs);
  const problemsMs = percentiles(siteKeys.problemsMs);
  const [heapStart, heapEnd] = [heap[0], heap[heap.length - 1]];
  const heapChange = (heapEnd - heapStart) / heapStart;
  const rows = [
    ['overview, 100 sensors: frames', `>= ${GOAL_FPS} every second`, fps(shown), verdict(shown.min >= GOAL_FPS)],
    ['overview, 100 sensors: JS heap after GC, start -> end', 'within 10 %',
      `${heapStart.toFixed(1)} -> ${heapEnd.toFixed(1)} MB (${(heapChange * 100).toFixed(1)} %)`,
      verdict(Math.abs(heapChange) <= GOAL_HEAP_RATIO)],
    ['overview, 100 sensors: keystroke in the filter to the cards shown', `< ${GOAL_KEY_MS} ms`, keys(filterMs),
      verdict(filterMs.max < GOAL_KEY_MS)],
    ['overview, 100 sensors: problem-only on/off (Space) to the cards shown', `< ${GOAL_KEY_MS} ms`,
      `${keys(problemsMs)}; ${siteKeys.problemsShown} shown`, verdict(problemsMs.max < GOAL_KEY_MS)],
    ['baseline: idle page, same load', '', fps(idle), ''],
    ['baseline: demo overview, 7 sensors', '', `${fps(demoFrames)}; filter ${keys(percentiles(demoKeys.filterMs))}`, ''],
  ];
  console.log(`The overview at a site's size: ${UDP_SENSORS} LS5 over UDP at ${RATE_HZ}/s each ` +
    `(${served.toFixed(0)} samples/s served) and ${ABSENT} on absent ports, ${elapsed.toFixed(0)} s ` +
    `after ${WARMUP_S} s of warm-up, headless chromium 1400 x 900; the service used ` +
    `${(serviceCpu * 100).toFixed(1)} % of a core and cut the page's stream off ${cuts} times; load average ${load.map((value) => value.toFixed(1)).join(' ')}`);
  console.log('');
  console.log('| figure | goal | this run | |');
  console.log('|---|---|---|---|');
  for (const row of rows) console.log(`| ${row.join(' | ')} |`);
  console.log('');
  console.log(`JS heap every ${HEAP_EVERY_S} s (MB): ${heap.map((value) => value.toFixed(1)).join(' ')}`);
  console.log(`${rows.filter((row) => row[3] === 'met').length} of ${rows.filter((row) => row[3]).length} goals met.`);
  if (profile) printProfile(profile);
} finally {
  await browser?.close();
  for (const child of children.reverse()) await stopped(child);
  rmSync(dir, { recursive: true, force: true });
}
