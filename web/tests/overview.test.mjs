// Browser tests of the overview page: headless chromium (playwright-core) against `rangekit
// serve --demo`, run by ctest (browser.overview). Every wait is on a condition of the page;
// the one time bound is the 2 s within which a killed emulator's card shows disconnected.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { cli, emulatorOn, launch, restartEmulator, screenshots, stopped, WAIT, waitForLine, watchErrors } from './support.mjs';

let serve;
let restarted;
let url;
let demoDir;
let browser;
let page;
let pageErrors;

const card = (name) => `[data-sensor="${name}"]`;

function connectedIs(name, connected) {
  return page.waitForFunction(
    ([selector, want]) => document.querySelector(selector)?.getAttribute('data-connected') === want,
    [card(name), String(connected)],
    WAIT,
  );
}

before(async () => {
  serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const dirPromise = waitForLine(serve, /pseudo-terminals in (\S+)/, 'emulator folder');
  const urlPromise = waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  demoDir = await dirPromise;
  url = await urlPromise;
  serve.stdout.resume();  // the service's per-second summary lines, not needed
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1400, height: 720 } });
  pageErrors = watchErrors(page);
  await page.goto(url);
});

after(async () => {
  await browser?.close();
  await stopped(restarted);
  await stopped(serve);
});

test('the page lists every sensor of the demo, each with its family', async () => {
  await page.waitForFunction(() => document.querySelectorAll('.card').length === 7, null, WAIT);
  const cards = await page.$$eval('.card', (found) =>
    found.map((element) => [element.dataset.sensor, element.querySelector('.family').textContent]));
  assert.deepEqual(cards, [
    ['belt', 'LS5'], ['belt-udp', 'LS5'], ['silo', 'ULS'],
    ['bay-A', 'ULS'], ['bay-B', 'ULS'], ['bay-C', 'ULS'], ['bay-D', 'ULS'],
  ]);
  // The demo writes to no historian: the cards' poll found no sink, and nothing of them shows.
  assert.equal(await page.isHidden('#sinks'), true);
  assert.equal(await page.$$eval('.sink', (found) => found.length), 0);
});

test('the live value updates on a card (bay-C: a level rising and falling)', async () => {
  const value = `${card('bay-C')} .value`;
  await page.waitForFunction((selector) => /^\d/.test(document.querySelector(selector)?.textContent ?? ''), value, WAIT);
  const first = await page.textContent(value);
  await page.waitForFunction(([selector, was]) => document.querySelector(selector).textContent !== was,
    [value, first], WAIT);
  assert.match(await page.textContent(`${card('bay-C')} .unit`), /^m$/);
  // The sparkline has drawn (uPlot's canvas) and holds some seconds of readings.
  await page.waitForSelector(`${card('bay-C')} .spark canvas`, { timeout: WAIT.timeout });
  await page.waitForFunction((selector) => Number(document.querySelector(selector).dataset.points) >= 24,
    card('bay-C'), WAIT);
  await page.screenshot({ path: path.join(screenshots, 'overview.png') });
});

// U113: §3 "A distance is not produced" in look down; bay-B is in look down (§8 US "n = 3"), and
// its reading is the trip signal's state (§2 "the on/off condition of the trip signal").
test('a ULS in look down shows whether a target is there, not a distance or no signal (U113)', async () => {
  await page.waitForFunction((selector) => /^(target present|no target)$/.test(document.querySelector(selector)?.textContent),
    `${card('bay-B')} .value`, WAIT);
  assert.equal(await page.getAttribute(card('bay-B'), 'data-reading'), 'live');
  assert.equal(await page.textContent(`${card('bay-B')} .unit`), '');
});

test('every input has a label and the page is usable with the keyboard alone', async () => {
  const unlabelled = await page.$$eval('input, select, textarea, button', (controls) =>
    controls.filter((control) => !(control.labels?.length || control.getAttribute('aria-label') ||
      (control.tagName === 'BUTTON' && control.textContent.trim())))
      .map((control) => control.outerHTML));
  assert.deepEqual(unlabelled, []);
  await page.keyboard.press('Tab');
  assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Skip to the sensors');
  await page.keyboard.press('Tab');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'filter');
  await page.keyboard.type('bay');
  await page.waitForFunction(() =>
    [...document.querySelectorAll('.card')].filter((element) => !element.hidden).length === 4, null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'keyboard-filter.png') });
  await page.keyboard.press('Tab');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'problems');
  await page.keyboard.press('Space');
  assert.equal(await page.isChecked('#problems'), true);
  await page.keyboard.press('Space');
  assert.equal(await page.isChecked('#problems'), false);
  // Back to the filter, cleared from the keyboard: every card again.
  await page.keyboard.press('Shift+Tab');
  await page.keyboard.press('Control+A');
  await page.keyboard.press('Backspace');
  await page.waitForFunction(() =>
    [...document.querySelectorAll('.card')].every((element) => !element.hidden), null, WAIT);
  // The cards' names come next in the tab order: each a link to the sensor's page.
  await page.keyboard.press('Tab');
  await page.keyboard.press('Tab');
  const focused = await page.evaluate(() => ({
    name: document.activeElement.textContent,
    href: document.activeElement.getAttribute('href'),
    card: document.activeElement.closest('.card')?.dataset.sensor,
  }));
  assert.deepEqual(focused, { name: 'belt', href: '#/sensor/belt', card: 'belt' });
  await page.screenshot({ path: path.join(screenshots, 'keyboard-focus.png') });
  // The skip link takes the focus to the sensors.
  await page.keyboard.press('Shift+Tab');
  await page.keyboard.press('Shift+Tab');
  await page.keyboard.press('Shift+Tab');
  assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Skip to the sensors');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => document.activeElement.id === 'sensors', null, WAIT);
});

// §2 "Icons: Displayed above the black measurement window, show measurement and the main parameters."
const ICON_MEANINGS = {
  'Laser On': 'The laser is firing.',
  'G': 'Gates are set.',
  'CT': 'Cooperative Target.',
  'O': 'an Offset value is being applied to measurements.',
  'BM': 'The ULS is producing valid measurements more than once every two seconds.',
};

const indicatorIs = (key, state) => page.waitForFunction(([which, want]) =>
  document.querySelector(`[data-indicator="${which}"]`)?.dataset.state === want, [key, state], WAIT);

test('the ULS page: §2 indicators with their meanings, the live reading, the display choice, Read (U114, U115)', async () => {
  // From the keyboard: the card's name is the way in.
  await page.focus('a[href="#/sensor/bay-C"]');
  await page.keyboard.press('Enter');
  await page.waitForSelector('.sensor-page[data-sensor="bay-C"]', { timeout: WAIT.timeout });
  const indicators = await page.$$eval('.indicator', (items) =>
    items.map((item) => [item.firstChild.textContent, item.title]));
  assert.equal(indicators.length, 6);
  for (const [label, meaning] of Object.entries(ICON_MEANINGS)) {
    const found = indicators.find(([text]) => text === label);
    assert.ok(found, `no ${label} indicator`);
    assert.ok(found[1].startsWith('The specification: "') && found[1].includes(meaning) && !found[1].includes('§'),
      `${label}'s tooltip "${found[1]}" does not quote the specification's "${meaning}" in words`);
  }
  await page.waitForFunction(() => /^\d+\.\d{3} m$/.test(document.querySelector('.measurement').textContent),
    null, WAIT);
  await indicatorIs('connected', 'on');
  await indicatorIs('laser', 'on');  // bay-C measures in averaging (US 7)
  await indicatorIs('basic', 'on');  // U115: readings several times a second
  // U114: gates, cooperative target and offset are known once the settings have been read.
  const unread = await page.$eval('[data-indicator="gates"]', (item) => item.dataset.state);
  assert.ok(unread === 'unknown' || unread === 'off', unread);
  await page.getByRole('button', { name: 'Read', exact: true }).focus();
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => document.querySelector('.page-message').textContent === 'Settings read.', null, WAIT);
  await indicatorIs('gates', 'off');  // the emulator's factory settings: no gate, no CT, no offset
  await indicatorIs('cooperative', 'off');
  await indicatorIs('offset', 'off');
  // Averaging: Distance, Intensity or Both (§2), each labelled; arrow keys move the choice.
  const labels = await page.$$eval('.display input', (inputs) => inputs.map((input) => input.labels[0].textContent));
  assert.deepEqual(labels, ['Distance', 'Intensity', 'Both']);
  await page.focus('#display-distance');
  await page.keyboard.press('ArrowRight');
  assert.equal(await page.isChecked('#display-intensity'), true);
  await page.waitForFunction(() => /^\d+\.\d{3} ns$/.test(document.querySelector('.measurement').textContent),
    null, WAIT);
  await page.keyboard.press('ArrowRight');
  await page.waitForFunction(() => / m · .* ns$/.test(document.querySelector('.measurement').textContent), null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'uls-page.png') });

  // Binning (bay-A): first or last target; look down (bay-B): ON/OFF, no choice.
  await page.evaluate(() => { location.hash = '#/sensor/bay-A'; });
  await page.waitForFunction(() =>
    [...document.querySelectorAll('.display input')].map((input) => input.labels[0].textContent).join() ===
      'First target,Last target', null, WAIT);
  await page.check('#display-last');
  await page.waitForFunction(() => /\(last of \d+\)$/.test(document.querySelector('.measurement').textContent),
    null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'uls-page-binning.png') });
  await page.evaluate(() => { location.hash = '#/sensor/bay-B'; });
  await page.waitForFunction(() => /^(ON|OFF)$/.test(document.querySelector('.measurement')?.textContent ?? ''),
    null, WAIT);
  assert.equal(await page.$$eval('.display input', (inputs) => inputs.length), 0);
  const unlabelled = await page.$$eval('input, select, textarea, button', (controls) =>
    controls.filter((control) => !(control.labels?.length || control.getAttribute('aria-label') ||
      (control.tagName === 'BUTTON' && control.textContent.trim())))
      .map((control) => control.outerHTML));
  assert.deepEqual(unlabelled, []);
  // Back to the overview from the keyboard.
  await page.focus('a.back');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => !document.getElementById('overview').hidden, null, WAIT);
});

test('a killed emulator turns its card disconnected within 2 s and back when it returns', async () => {
  await connectedIs('belt', true);
  const emulator = emulatorOn(path.join(demoDir, 'ls5'));
  const killed = Date.now();
  process.kill(emulator.pid, 'SIGKILL');
  await connectedIs('belt', false);
  const seen = Date.now() - killed;
  console.log(`belt's card showed disconnected ${seen} ms after kill -9 of its emulator`);
  // A killed emulator turns its card to disconnected within 2 s (docs/dashboard.md).
  assert.ok(seen <= 2000, `disconnected shown after ${seen} ms`);
  assert.equal(await page.textContent(`${card('belt')} .state`), 'Disconnected');
  await page.screenshot({ path: path.join(screenshots, 'disconnected.png') });

  // The same emulator again on the same pty link.
  restarted = restartEmulator(emulator);
  await connectedIs('belt', true);
  await page.waitForFunction((selector) => document.querySelector(selector)?.dataset.reading !== 'stale',
    card('belt'), WAIT);
  assert.equal(await page.textContent(`${card('belt')} .state`), 'Connected');
  await page.screenshot({ path: path.join(screenshots, 'reconnected.png') });
});

test('the page raised no script error or policy violation', () => {
  assert.deepEqual(pageErrors, []);
});
