// Browser test of the sensor pages' live plot against `rangekit serve --demo`: a window of
// 10 s to 1 h, Pause, averaging as a line, binning as a scatter, look down as an ON/OFF trace,
// the LS5's derivative on an axis of its own (L80).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import path from 'node:path';
import { after, before, test } from 'node:test';
import {
  WAIT, cli, controlRequest, emulatorOn, launch, restartEmulator, screenshots, stopped, waitForLine, watchErrors,
} from './support.mjs';

let serve;
let restarted;
let serviceUrl;
let demoDir;
let browser;
let page;
let pageErrors;

before(async () => {
  serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const dirPromise = waitForLine(serve, /pseudo-terminals in (\S+)/, 'emulator folder');
  const url = await waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  demoDir = await dirPromise;
  serviceUrl = url;
  serve.stdout.resume();
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  pageErrors = watchErrors(page);
  await page.goto(`${url}#/sensor/bay-C`);
});

after(async () => {
  await browser?.close();
  await stopped(restarted);
  await stopped(serve);
});

// One request to the demo LS5 emulator's control socket (docs/emulator-ls5.md, "Control").
const ls5Control = (request) => controlRequest(path.join(demoDir, 'ls5.control'), request);

const points = () => page.evaluate(() => Number(document.querySelector('.live-plot')?.dataset.points ?? 0));

function pointsAtLeast(count) {
  return page.waitForFunction((want) => Number(document.querySelector('.live-plot')?.dataset.points ?? 0) >= want,
    count, WAIT);
}

test('averaging draws a line that grows, with a time window from 10 s to 1 h', async () => {
  await page.waitForFunction(() => document.querySelector('.live-plot')?.dataset.mode === 'averaging', null, WAIT);
  await pointsAtLeast(5);
  const windows = await page.$$eval('#plot-window option', (options) => options.map((option) => option.textContent));
  assert.deepEqual(windows, ['10 s', '1 min', '10 min', '1 h']);
  assert.equal(await page.evaluate(() => document.querySelector('#plot-window').labels[0].textContent), 'Time window');
  await page.selectOption('#plot-window', '10');
  assert.ok(await page.$('.live-plot canvas'));
  await page.screenshot({ path: path.join(screenshots, 'live-plot-averaging.png') });
});

test('Pause stops the drawn end while data keeps coming; Resume follows again', async () => {
  await page.getByRole('button', { name: 'Pause' }).focus();
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => document.querySelector('.live-plot').dataset.paused === 'true', null, WAIT);
  const end = await page.evaluate(() => document.querySelector('.live-plot').dataset.drawnEnd);
  const had = await points();
  await pointsAtLeast(had + 3);
  assert.equal(await page.evaluate(() => document.querySelector('.live-plot').dataset.drawnEnd), end);
  await page.getByRole('button', { name: 'Resume' }).click();
  await page.waitForFunction((before) => document.querySelector('.live-plot').dataset.drawnEnd !== before, end, WAIT);
});

test('a drag across the plot zooms into that span and pauses; Resume follows the live end again', async () => {
  const shown = () => page.evaluate(() => {
    const plot = document.querySelector('.live-plot');
    return { paused: plot.dataset.paused, min: Number(plot.dataset.xMin), max: Number(plot.dataset.xMax),
      end: Number(plot.dataset.drawnEnd) };
  });
  await page.waitForFunction(() => document.querySelector('.live-plot').dataset.xMax !== undefined, null, WAIT);
  const before = await shown();
  assert.equal(before.paused, 'false');
  assert.ok(Math.abs(before.max - before.min - 10) < 1e-6, `the 10 s window shows ${before.max - before.min} s`);
  // uPlot's own drag-select, with the mouse, across the middle half of the plot's area.
  const over = await page.$('.live-plot .u-over');
  const box = await over.boundingBox();
  const y = box.y + box.height / 2;
  await page.mouse.move(box.x + box.width * 0.25, y);
  await page.mouse.down();
  await page.mouse.move(box.x + box.width * 0.5, y, { steps: 5 });
  await page.mouse.move(box.x + box.width * 0.75, y, { steps: 5 });
  await page.mouse.up();
  await page.waitForFunction(() => document.querySelector('.live-plot').dataset.paused === 'true', null, WAIT);
  const zoomed = await shown();
  const span = zoomed.max - zoomed.min;
  // Half the width of the area: about 5 of the 10 s, inside the span shown before.
  assert.ok(span > 3.5 && span < 6.5, `zoomed to ${span} s`);
  assert.ok(zoomed.min >= before.min - 0.5 && zoomed.max <= before.max + 0.5, JSON.stringify({ before, zoomed }));
  assert.equal(await page.getByRole('button', { name: 'Resume' }).count(), 1);
  // Paused: points keep arriving, the zoomed span stays.
  await pointsAtLeast(Number(await points()) + 3);
  const still = await shown();
  assert.deepEqual([still.min, still.max], [zoomed.min, zoomed.max]);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-zoomed.png') });
  // Resume: the whole window again, its end following the newest point.
  await page.getByRole('button', { name: 'Resume' }).click();
  await page.waitForFunction((end) => Number(document.querySelector('.live-plot').dataset.drawnEnd) > end, still.end, WAIT);
  const resumed = await shown();
  assert.equal(resumed.paused, 'false');
  assert.ok(Math.abs(resumed.max - resumed.min - 10) < 1e-6, `resumed with ${resumed.max - resumed.min} s`);
  assert.ok(resumed.max > zoomed.max);
});

test('binning targets are a scatter; look down an ON/OFF trace', async () => {
  await page.evaluate(() => { location.hash = '#/sensor/bay-A'; });
  await page.waitForFunction(() => document.querySelector('.live-plot')?.dataset.mode === 'binning', null, WAIT);
  await pointsAtLeast(5);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-binning.png') });
  await page.evaluate(() => { location.hash = '#/sensor/bay-B'; });
  await page.waitForFunction(() => document.querySelector('.live-plot')?.dataset.mode === 'look-down', null, WAIT);
  await pointsAtLeast(5);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-look-down.png') });
});

// L80: LS5 manual §8.8: "The "Type of preliminary result" parameter switches the possibility of
// the result output either in a net form (distance from the beginning of the range), or as a
// derivative of the distance"; §8.9 (8.2) "distance derivate = range · (code − 25000) / 50000".
// A derivative is a difference of two results, so the plot gives it a second y axis of its own.
test('L80: an LS5 in derivative mode plots its derivative on a second axis, not the distance axis, gaps as gaps', async () => {
  await page.evaluate(() => { location.hash = '#/sensor/belt'; });
  await page.waitForFunction(() => document.querySelector('.live-plot')?.dataset.mode === 'ls5', null, WAIT);
  await page.selectOption('#plot-window', '10');
  await pointsAtLeast(300);  // 3 s of the demo's 100 results a second: a line to see on the screenshots
  assert.equal(await page.evaluate(() => document.querySelector('.live-plot').dataset.axes), 'distance (mm)');
  // The 10 s window's time labels on this wide plot have room between them: the widest label
  // (its first line, measured in the axis font) plus 16 px fits in the spacing of the ticks.
  const room = await page.evaluate(() => {
    const plot = document.querySelector('.live-plot');
    const labels = (plot.dataset.xLabels ?? '').split('|').filter(Boolean);
    const context = document.createElement('canvas').getContext('2d');
    context.font = '12px system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, "Noto Sans", sans-serif';
    // The first label carries the date on a line of its own, below the others.
    const widest = Math.max(...labels.map((label) => context.measureText(label.split('\n')[0]).width));
    return { labels, widest, spacing: plot.querySelector('.u-over').getBoundingClientRect().width / labels.length };
  });
  assert.ok(room.labels.length >= 4 && room.spacing >= room.widest + 16, JSON.stringify(room));
  await page.screenshot({ path: path.join(screenshots, 'live-plot-ls5.png') });
  // Table 9.2 parameter 0E = 01 written to the demo's emulated LS5 through the service (the
  // page is not involved), as `rangekit ls5 set result-type=derivative` writes it.
  const response = await fetch(new URL('/api/sensors/belt/settings', serviceUrl), {
    method: 'PATCH', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ 'result-type': 'derivative' }),
  });
  const written = await response.text();
  assert.equal(response.status, 200, written);
  assert.equal(JSON.parse(written)['result-type'], 'derivative');
  await page.waitForFunction(() => document.querySelector('.live-plot').dataset.axes === 'distance (mm)|derivative (mm)',
    null, WAIT);
  assert.equal(await page.evaluate(() => document.querySelector('.live-plot').dataset.series),
    'distance (mm)|derivative (mm)');
  const counts = () => page.evaluate(() => (document.querySelector('.live-plot').dataset.values ?? '0|0').split('|').map(Number));
  const [distances, derivatives] = await counts();
  // New derivatives keep coming on their own series; the distance series gets none of them.
  await page.waitForFunction((had) => Number(document.querySelector('.live-plot').dataset.values.split('|')[1]) >= had + 300,
    derivatives, WAIT);
  assert.equal((await counts())[0], distances);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-ls5-derivative.png') });

  // §8.9 "65535 – to indicate that there is no signal" (docs/emulator-ls5.md: a target beyond lower
  // boundary + range, 8.1234 + 40.001 mm here): samples without a derivative are rows of gaps, and
  // the derivative resumes after them without being joined across (spanGaps off).
  const gaps = () => page.evaluate(() => Number(document.querySelector('.live-plot').dataset.gaps));
  const gapsBefore = await gaps();
  await ls5Control({ cmd: 'move_target', position_mm: 100, speed_mm_per_s: 0, reflectivity: 1 });
  await page.waitForFunction((had) => Number(document.querySelector('.live-plot').dataset.gaps) >= had + 50, gapsBefore, WAIT);
  const [, derivativesInGap] = await counts();
  await ls5Control({ cmd: 'move_target', position_mm: 30, speed_mm_per_s: 2, reflectivity: 1 });
  await page.waitForFunction((had) => Number(document.querySelector('.live-plot').dataset.values.split('|')[1]) >= had + 100,
    derivativesInGap, WAIT);
  assert.ok(await gaps() >= gapsBefore + 50);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-ls5-derivative-gap.png') });
  const back = await fetch(new URL('/api/sensors/belt/settings', serviceUrl), {
    method: 'PATCH', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ 'result-type': 'pure' }),
  });
  assert.equal(back.status, 200, await back.text());  // the text only once the status is read
});

test('a killed ULS emulator leaves a gap in the plot, not a line across; the trace resumes after', async () => {
  // silo, alone on its pty (averaging, Continuous Output on): kill -9 of its emulator as the
  // overview test does, then the same emulator again on the same pty link.
  await page.evaluate(() => { location.hash = '#/sensor/silo'; });
  await page.waitForFunction(() => document.querySelector('.live-plot')?.dataset.mode === 'averaging', null, WAIT);
  await page.selectOption('#plot-window', '60');  // the outage and both sides of it in the picture
  await pointsAtLeast(20);
  const shown = () => page.evaluate(() => {
    const plot = document.querySelector('.live-plot');
    return { values: Number(plot.dataset.values), gaps: Number(plot.dataset.gaps),
      lastGap: Number(plot.dataset.lastGap), lastValue: Number(plot.dataset.lastValue) };
  });
  const emulator = emulatorOn(path.join(demoDir, 'uls'));
  const killed = Date.now() / 1000;
  process.kill(emulator.pid, 'SIGKILL');
  await page.waitForFunction(() => document.querySelector('[data-indicator="connected"]')?.dataset.state === 'off',
    null, WAIT);
  // The plot marks a gap once the silence passes its 2 s; wait for that row, not for a time.
  await page.waitForFunction((since) => {
    const plot = document.querySelector('.live-plot');
    return Number(plot.dataset.lastGap) >= since && Number(plot.dataset.lastGap) > Number(plot.dataset.lastValue);
  }, killed, WAIT).catch(() => {});
  const down = await shown();
  // The disconnection's row of gaps (no value in any series) is the newest row, after the last
  // distance: with spanGaps off, uPlot draws no line across a null, so nothing joins the two sides.
  assert.ok(down.lastGap >= killed && down.lastGap > down.lastValue, JSON.stringify({ killed, down }));
  restarted = restartEmulator(emulator);
  await page.waitForFunction((had) => Number(document.querySelector('.live-plot').dataset.values) >= had + 20,
    down.values, WAIT);
  const after = await shown();
  // The trace resumes after the gap, which stays where it was (at least one row of gaps between).
  assert.ok(after.gaps >= down.gaps && after.lastValue > down.lastGap, JSON.stringify({ down, after }));
  assert.equal(await page.evaluate(() => document.querySelector('.live-plot').dataset.series), 'distance (m)');
  await page.waitForFunction(() => document.querySelector('[data-indicator="connected"]')?.dataset.state === 'on',
    null, WAIT);
  console.log(`silo: back ${(after.lastValue - killed).toFixed(1)} s after kill -9, ${after.gaps} rows of gaps in all`);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-uls-gap.png') });
});

test('the page raised no script error or policy violation', () => {
  assert.deepEqual(pageErrors, []);
});
