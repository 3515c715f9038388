// Browser test of the ULS page's live plot (issue 14 point 5): uPlot, a time window of 10 s
// to 1 h, Pause, averaging as a line, binning targets as a scatter, look down as an ON/OFF
// trace; against `rangekit serve --demo` (bay-C averaging, bay-A binning, bay-B look down).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { cli, launch, screenshots, stopped, WAIT, waitForLine, watchErrors } from './support.mjs';

let serve;
let browser;
let page;
let pageErrors;

before(async () => {
  serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const url = await waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  serve.stdout.resume();
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  pageErrors = watchErrors(page);
  await page.goto(`${url}#/sensor/bay-C`);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
});

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

test('binning targets are a scatter; look down an ON/OFF trace', async () => {
  await page.evaluate(() => { location.hash = '#/sensor/bay-A'; });
  await page.waitForFunction(() => document.querySelector('.live-plot')?.dataset.mode === 'binning', null, WAIT);
  await pointsAtLeast(5);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-binning.png') });
  await page.evaluate(() => { location.hash = '#/sensor/bay-B'; });
  await page.waitForFunction(() => document.querySelector('.live-plot')?.dataset.mode === 'look_down', null, WAIT);
  await pointsAtLeast(5);
  await page.screenshot({ path: path.join(screenshots, 'live-plot-look-down.png') });
});

test('the page raised no script error or policy violation', () => {
  assert.deepEqual(pageErrors, []);
});
