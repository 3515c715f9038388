// Browser test: a capture started and stopped on the page downloads a `.log` with the §2
// columns for each mode (`rangekit serve --demo`: bay-C averages, bay-A bins, bay-B looks
// down); SQLite and CSV are offered too. Screenshots in RANGEKIT_SCREENSHOTS.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { readFileSync } from 'node:fs';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { cli, launch, screenshots, stopped, WAIT, waitForLine, watchErrors } from './support.mjs';

let serve;
let url;
let browser;
let page;
let pageErrors;

before(async () => {
  serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  url = await waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  serve.stdout.resume();
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1400, height: 900 }, acceptDownloads: true });
  pageErrors = watchErrors(page);
  await page.goto(url);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
});

// Downloads the file behind the capture's link of `format` and returns its path.
async function download(format) {
  const [file] = await Promise.all([
    page.waitForEvent('download', { timeout: WAIT.timeout }),
    page.click(`.capture a[data-format="${format}"]`),
  ]);
  return { name: file.suggestedFilename(), path: await file.path() };
}

// Start Capture, wait for `records` samples (the page's own count), Stop Capture; the .log's lines.
async function captureOn(sensor, records) {
  await page.evaluate((name) => { location.hash = `#/sensor/${name}`; }, sensor);
  await page.waitForSelector(`.sensor-page[data-sensor="${sensor}"] .capture`, { timeout: WAIT.timeout });
  await page.getByRole('button', { name: 'Start Capture' }).click();
  await page.waitForFunction((want) => {
    const match = /capturing, (\d+) samples/.exec(document.querySelector('.capture-status')?.textContent ?? '');
    return match && Number(match[1]) >= want;
  }, records, WAIT);
  await page.getByRole('button', { name: 'Stop Capture' }).click();
  await page.waitForFunction(() => document.querySelector('.capture')?.dataset.capture === 'stopped', null, WAIT);
  const log = await download('log');
  assert.match(log.name, /\.log$/);
  return readFileSync(log.path, 'utf8').split('\n').filter(Boolean);
}

// §2 File Menu: "Averaging Mode: Time (H:M:S:mS), Distance, Units, Intensity." (U100)
test('averaging (bay-C): the .log has Time, Distance, Units, Intensity', async () => {
  const lines = await captureOn('bay-C', 5);
  assert.equal(lines[0], 'Time (H:M:S:mS), Distance, Units, Intensity');
  assert.ok(lines.length >= 6, lines.join('\n'));
  for (const line of lines.slice(1)) assert.match(line, /^\d\d:\d\d:\d\d:\d{3}, (\d+\.\d{3}, m, \d*|ERROR \d+)$/);
  // View Capture shows the same file on the page.
  await page.getByRole('button', { name: 'View Capture' }).click();
  await page.waitForFunction(() => document.querySelector('.capture-view')?.textContent
    .startsWith('Time (H:M:S:mS), Distance, Units, Intensity'), null, WAIT);
  // SQLite (offered once stopped) and CSV.
  const sqlite = readFileSync((await download('sqlite')).path);
  assert.equal(sqlite.subarray(0, 16).toString('latin1'), 'SQLite format 3\0');
  const csv = readFileSync((await download('csv')).path, 'utf8');
  assert.ok(csv.split('\n').filter(Boolean).length >= 6, csv);
  await page.screenshot({ path: path.join(screenshots, 'capture-averaging.png') });
});

// "Binning Mode: Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units."
test('binning (bay-A): the .log has Time, Index, Number of Targets, Distance, Units', async () => {
  const lines = await captureOn('bay-A', 5);
  assert.equal(lines[0], 'Time (H:M:S:mS), Index value in array, Number of Targets, Distance, Units');
  assert.ok(lines.length >= 6, lines.join('\n'));
  for (const line of lines.slice(1)) assert.match(line, /^\d\d:\d\d:\d\d:\d{3}, (\d+, \d+, \d+\.\d{3}, m|ERROR \d+)$/);
  await page.screenshot({ path: path.join(screenshots, 'capture-binning.png') });
});

// "Look Down Mode: (H:M:S:mS), ON/OFF."
test('look down (bay-B): the .log has Time and ON/OFF', async () => {
  const lines = await captureOn('bay-B', 5);
  assert.equal(lines[0], 'Time (H:M:S:mS), ON/OFF');
  assert.ok(lines.length >= 2, lines.join('\n'));
  for (const line of lines.slice(1)) assert.match(line, /^\d\d:\d\d:\d\d:\d{3}, (ON|OFF|ERROR \d+)$/);
  await page.screenshot({ path: path.join(screenshots, 'capture-look-down.png') });
});

test('the capture controls are labelled and reached from the keyboard', async () => {
  const unlabelled = await page.$$eval('.capture button, .capture a', (controls) =>
    controls.filter((control) => !control.textContent.trim()).map((control) => control.outerHTML));
  assert.deepEqual(unlabelled, []);
  await page.getByRole('button', { name: 'Start Capture' }).focus();
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => document.querySelector('.capture')?.dataset.capture === 'active', null, WAIT);
  // Start Capture is disabled while capturing; Stop Capture, enabled now, takes the Enter.
  await page.getByRole('button', { name: 'Stop Capture' }).focus();
  assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Stop Capture');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => document.querySelector('.capture')?.dataset.capture === 'stopped', null, WAIT);
});

test('the page raised no script error or policy violation', () => {
  assert.deepEqual(pageErrors, []);
});
