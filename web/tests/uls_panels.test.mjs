// Browser tests of the ULS page's parameter panels (U119): PRF changed in the emulator, an
// out-of-range value refused before sending, a unit's refusal shown with its §10 text, labels
// and keyboard use. Screenshots in RANGEKIT_SCREENSHOTS.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import path from 'node:path';
import { after, before, test } from 'node:test';
import {
  WAIT, cli, controlRequest, launch, screenshots, sectionsOutsideFoot, selectsTooNarrow, stopped, waitForLine, watchErrors,
} from './support.mjs';

let serve;
let demoDir;
let browser;
let page;
let pageErrors;
const patches = [];

// One request to the demo bus emulator's control socket (docs/emulator-uls.md, "Control").
const control = (request) => controlRequest(path.join(demoDir, 'bus.control'), request);

const prfOfUnit = async (unit) => (await control({ cmd: 'outputs', device: unit })).prf_hz;
const message = () => page.textContent('.panel-message');

before(async () => {
  serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const dirPromise = waitForLine(serve, /pseudo-terminals in (\S+)/, 'emulator folder');
  const urlPromise = waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  demoDir = await dirPromise;
  const url = await urlPromise;
  serve.stdout.resume();
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1400, height: 1300 } });
  pageErrors = watchErrors(page);
  page.on('request', (request) => {
    if (request.method() === 'PATCH') patches.push(request.url());
  });
  await page.goto(`${url}#/sensor/bay-C`);
  // Every field waits for the settings: Read fetches them (§2 "Read").
  await page.waitForSelector('#setting-prf-hz', WAIT);
  await page.getByRole('button', { name: 'Read', exact: true }).click();
  await page.waitForFunction(() => document.querySelector('#setting-prf-hz')?.disabled === false, null, WAIT);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
});

test('each §2 panel shows its fields with the range and unit of the document', async () => {
  const legends = await page.$$eval('.panels .panel legend', (items) => items.map((item) => item.textContent));
  assert.deepEqual(legends, ['Basic Setup', 'Measurement Mode', 'PRF and Pulses/Measure', 'Averaging Parameters',
    'Laser Power', 'Output Setup', 'Binning Parameters', 'Look Down', 'Current Loop']);
  // §2 "PRF ... Values range from 10 to 5000"; §8 Short Gate "0-1700 m" (U18).
  assert.match(await page.textContent('#setting-prf-hz-range'), /10 – 5000 Hz/);
  assert.match(await page.textContent('#setting-short-gate-m-range'), /0 – 1700 m/);
  // §2 Binning Parameters "Bin Size (Range) 2.5 (13)" (U33).
  const binSizes = await page.$$eval('#setting-bin-size option', (options) => options.map((option) => option.textContent));
  assert.equal(binSizes[0], '2.5 (13)');
  assert.equal(await page.inputValue('#setting-prf-hz'), '2000,2000,2000');  // §2's screen: "PRF 2000 Hz"
  // The bus runs with Continuous Output off (§7), so Single Measurement is offered (§2),
  // printed at the unit's resolution: §9 "Resolution 1 mm or 0.01 ft" (not "27.881000 m").
  await page.getByRole('button', { name: 'Single Measurement' }).click();
  await page.waitForFunction(() => /Single Measurement: done \(/.test(document.querySelector('.page-message').textContent),
    null, WAIT);
  assert.match(await page.textContent('.page-message'), /^Single Measurement: done \(\d+\.\d{3} m\)\.$/);
  await page.screenshot({ path: path.join(screenshots, 'uls-panels.png'), fullPage: true });
});

test('changing PRF on the page changes it in the emulator, from the keyboard alone', async () => {
  assert.deepEqual(await prfOfUnit('C'), [2000, 2000, 2000]);
  await page.focus('#setting-prf-hz');
  await page.keyboard.press('Control+A');
  await page.keyboard.type('1000,2000,3000');
  // Tab from the field back to Upload Settings is long; Shift+Tab through the page is not
  // needed: the button is reached by focus and pressed with Enter, as a keyboard user does.
  await page.getByRole('button', { name: 'Upload Settings' }).focus();
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => /Uploaded and read back: prf-hz/.test(document.querySelector('.panel-message').textContent),
    null, WAIT);
  assert.deepEqual(await prfOfUnit('C'), [1000, 2000, 3000]);  // §8 $PF,a,b,c: averaging, binning, look down
  assert.equal(patches.length, 1);
});

test('an out-of-range PRF shows the error and sends nothing', async () => {
  const before = patches.length;
  await page.fill('#setting-prf-hz', '6000,2000,3000');
  // Shown as it is typed, before anything is sent: §8 PF 10-5000 Hz, §10 32 "Invalid PRF".
  await page.waitForFunction(() => document.querySelector('#setting-prf-hz').getAttribute('aria-invalid') === 'true',
    null, WAIT);
  assert.match(await page.textContent('#setting-prf-hz-problem'), /6000 is out of range: 10 – 5000 Hz \(the ULS answers error 32\)/);
  await page.getByRole('button', { name: 'Upload Settings' }).click();
  await page.waitForFunction(() => /^Nothing sent: prf-hz/.test(document.querySelector('.panel-message').textContent),
    null, WAIT);
  // The decision is taken before any request: nothing on the network log, the unit unchanged.
  assert.equal(patches.length, before);
  assert.deepEqual(await prfOfUnit('C'), [1000, 2000, 3000]);
  assert.equal(await page.evaluate(() => document.activeElement.id), 'setting-prf-hz');  // focus on the field at fault
  await page.screenshot({ path: path.join(screenshots, 'uls-panels-out-of-range.png'), fullPage: true });
  await page.fill('#setting-prf-hz', '1000,2000,3000');
  await page.waitForFunction(() => document.querySelector('#setting-prf-hz').getAttribute('aria-invalid') === 'false',
    null, WAIT);
});

test("a unit's refusal shows its §10 number and Interface display text", async () => {
  // In range for §8 AW (1-65535) but over the 1024 pulses a measurement: the unit answers 49.
  await page.fill('#setting-averaging-weight', '60000');
  await page.getByRole('button', { name: 'Upload Settings' }).click();
  await page.waitForFunction(() => /^Upload refused/.test(document.querySelector('.panel-message').textContent), null, WAIT);
  // §10: "49 | Pulse Per Output Must Be Greater Than Average Weight | PPO Must Be Greater Than Average Weight".
  assert.match(await message(), /^Upload refused: ULS error 49: PPO Must Be Greater Than Average Weight \(/);
  await page.screenshot({ path: path.join(screenshots, 'uls-panels-device-error.png'), fullPage: true });
  await page.getByRole('button', { name: 'Read', exact: true }).click();  // the field shows the unit's value again
  await page.waitForFunction(() => document.querySelector('#setting-averaging-weight').value === '992', null, WAIT);
});

// §2 Look Down "the Short Timeout option allows you to setup the sensor quicker"; §3 "If the short
// timeout period is selected in the ULS interface, the unit will re-reference in 8,000 laser pulses"
// (U21: TT takes the pulse count, 8000 = 1F40). The unit's TT is read from the emulator's control
// socket, not through the page. docs/conformance.md U109.
test('U109: Short Timeout sets the re-reference time to 8000 pulses in the unit, and unchecking restores the typed time', async () => {
  const pulsesOfUnit = async () => (await control({ cmd: 'outputs', device: 'C' })).trip_timeout_pulses;
  assert.equal(await pulsesOfUnit(), 1080000);  // §3 "1,080,000 laser pulses or approximately 6 minutes"
  assert.equal(await page.inputValue('#setting-trip-timeout-s'), '360');
  assert.equal(await page.isChecked('#setting-short-timeout'), false);
  await page.fill('#setting-trip-timeout-s', '120');
  await page.check('#setting-short-timeout');
  assert.equal(await page.inputValue('#setting-trip-timeout-s'), '2.6667');  // 8000 / 3000 s
  assert.equal(await page.getAttribute('#setting-trip-timeout-s', 'readonly'), '');
  await page.screenshot({ path: path.join(screenshots, 'uls-panels-short-timeout.png'), fullPage: true });
  await page.getByRole('button', { name: 'Upload Settings' }).click();
  await page.waitForFunction(() => /Uploaded and read back: trip-timeout-s\.$/.test(document.querySelector('.panel-message').textContent),
    null, WAIT);
  assert.equal(await pulsesOfUnit(), 8000);
  // Read shows the box checked when the unit's TT is 8000 pulses (unchecked here first, so it is Read that checks it).
  await page.uncheck('#setting-short-timeout');
  await page.getByRole('button', { name: 'Read', exact: true }).click();
  await page.waitForFunction(() => document.querySelector('#setting-short-timeout').checked, null, WAIT);
  assert.equal(await page.inputValue('#setting-trip-timeout-s'), '2.6667');
  await page.uncheck('#setting-short-timeout');
  assert.equal(await page.inputValue('#setting-trip-timeout-s'), '120');  // the time typed before
  assert.equal(await page.getAttribute('#setting-trip-timeout-s', 'readonly'), null);
  await page.fill('#setting-trip-timeout-s', '360');
  await page.getByRole('button', { name: 'Upload Settings' }).click();
  await page.waitForFunction(() => /Uploaded and read back: trip-timeout-s\.$/.test(document.querySelector('.panel-message').textContent),
    null, WAIT);
  assert.equal(await pulsesOfUnit(), 1080000);
});

// U41 (Minimum Pulse Width) and U108 (current loop calibration): §2 shows both, §8 has no command
// for either, so each is an explanation in its panel, with no input.
test('U108: Minimum Pulse Width and current loop calibration are explanations without an input', async () => {
  for (const [panel, id, words] of [
    ['Averaging Parameters', 'note-min-pulse-width', /The specification: "This value is used to reject returned receive pulses.*The serial protocol has no command.*U41/s],
    ['Current Loop', 'note-current-loop-calibration', /The specification's "Calibrating the Current Loop".*DAC values.*SAVE.*The serial protocol has no command.*U108/s],
  ]) {
    const found = await page.$eval(`#${id}`, (note) => ({
      legend: note.closest('fieldset')?.querySelector('legend')?.textContent,
      text: note.textContent,
      controls: note.querySelectorAll('input, select, textarea, button').length,
      visible: note.getBoundingClientRect().height > 0,
    }));
    assert.equal(found.legend, panel);
    assert.match(found.text, words);
    assert.equal(found.controls, 0);
    assert.equal(found.visible, true);
  }
  await page.$eval('#note-current-loop-calibration', (note) => note.scrollIntoView());
  await page.screenshot({ path: path.join(screenshots, 'uls-panels-no-command.png') });
});

test('the page names the specification\'s sections once, in its foot, and says everything else in words', async () => {
  // Panels, notes, tooltips of the fields and indicators, the network and capture windows: all read.
  assert.equal(await page.textContent('#sensor-view > footer.document-sections'), 'ULS interface specification: §2 Interface Program, §3 measurement modes, §7 RS-485 network, ' +
    '§8 commands and formats, §9 rates and resolution, §10 errors; docs/conformance.md.');
  assert.deepEqual(await sectionsOutsideFoot(page), []);
});

test('no select of the panels is too narrow for its choices', async () => {
  // Each select is at least as wide as the browser makes one with the same choices left to
  // its natural width (a hidden copy, same font): its longest choice then shows whole.
  const cut = await selectsTooNarrow(page, '.panels select');
  assert.deepEqual(cut, []);
});

test('every new control has a label and Tab reaches every field of the panels', async () => {
  const unlabelled = await page.$$eval('input, select, textarea, button', (controls) =>
    controls.filter((control) => !(control.labels?.length || control.getAttribute('aria-label') ||
      (control.tagName === 'BUTTON' && control.textContent.trim())))
      .map((control) => control.outerHTML));
  assert.deepEqual(unlabelled, []);
  const fields = await page.$$eval('[data-setting]', (inputs) => inputs.map((input) => input.id));
  await page.focus(`#${fields[0]}`);
  const reached = [fields[0]];
  for (let step = 1; step < fields.length; ++step) {
    await page.keyboard.press('Tab');
    reached.push(await page.evaluate(() => document.activeElement.id));
  }
  assert.deepEqual(reached, fields);
  // A select is changed from the keyboard too (no upload: only the field changes).
  await page.focus('#setting-power');
  await page.keyboard.press('ArrowDown');
  assert.equal(await page.inputValue('#setting-power'), '1');
  await page.waitForFunction(() => document.querySelector('#setting-power').closest('.field').classList.contains('changed'),
    null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'uls-panels-keyboard.png') });
});

test('the family\'s actions the page does not place itself come from GET /api/families: Save and Reset', async () => {
  await page.waitForSelector('.sensor-page .other-actions button[data-action="reset"]', WAIT);
  assert.deepEqual(await page.$$eval('.sensor-page .other-actions button', (buttons) => buttons.map((b) => [b.textContent, b.title])),
    [['Save', 'the settings into non-volatile memory (SU)'], ['Reset', 'every setting to its factory value, then read back']]);
  await page.click('.sensor-page .other-actions button[data-action="save"]');
  await page.waitForFunction(() => document.querySelector('.sensor-page .page-message')?.textContent === 'Save: done.', null, WAIT);
});

test('the page raised no script error or policy violation', () => {
  // The one 502 is the refused upload above (docs/api.md: device_error), which chromium logs.
  const unexpected = pageErrors.filter((error) => !/status of 502 \(Bad Gateway\)/.test(error));
  assert.deepEqual(unexpected, []);
  assert.equal(pageErrors.length - unexpected.length, 1);
});
