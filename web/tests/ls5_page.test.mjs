// Browser tests of the LS5 page against `rangekit serve --demo` (L73-L76): ID, §8's formulas,
// parameters changed in the emulator or refused before sending, FX/FR latching, and labels
// and keyboard use. Screenshots in RANGEKIT_SCREENSHOTS.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import path from 'node:path';
import { after, before, test } from 'node:test';
import * as esbuild from 'esbuild';
import {
  WAIT, cli, controlRequest, launch, screenshots, sectionsOutsideFoot, selectsTooNarrow, stopped, waitForLine, watchErrors,
} from './support.mjs';

let serve;
let demoDir;
let browser;
let page;
let pageErrors;
let url;
const patches = [];

// One request to the demo LS5 emulator's control socket (docs/emulator-ls5.md, "Control").
const control = (request) => controlRequest(path.join(demoDir, 'ls5.control'), request);

const outputs = async () => {
  const answer = await control({ cmd: 'outputs' });
  return answer.devices ? answer.devices[0] : answer;
};
const panelMessage = () => page.textContent('.ls5-page .panel-message');

before(async () => {
  serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const dirPromise = waitForLine(serve, /pseudo-terminals in (\S+)/, 'emulator folder');
  const urlPromise = waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  demoDir = await dirPromise;
  url = await urlPromise;
  serve.stdout.resume();
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
  pageErrors = watchErrors(page);
  page.on('request', (request) => {
    if (request.method() === 'PATCH') patches.push(request.url());
  });
  // From the overview, as a user comes: the belt card's name opens its page.
  await page.goto(url);
  await page.click('a[href="#/sensor/belt"]', WAIT);
  await page.waitForFunction(() => document.querySelector('[data-id="version"]')?.textContent !== '–', null, WAIT);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
});

test('the decoded ID shows version, lower boundary, range and serial (§9.2)', async () => {
  // §9.2: "the device version (LS5.6.0), the lower boundary (8.1234 mm), the range (40.001 mm),
  // and the serial number (157)"; the demo emulator is that sensor on firmware LS5.12.0 (Ethernet).
  assert.equal(await page.textContent('[data-id="version"]'), 'LS5.12.0');
  assert.equal(await page.textContent('[data-id="lower-boundary-mm"]'), '8.1234 mm');
  assert.equal(await page.textContent('[data-id="range-mm"]'), '40.001 mm');
  assert.equal(await page.textContent('[data-id="serial"]'), '157');
  assert.equal(await page.textContent('[data-id="ethernet"]'), 'yes');
  await page.getByRole('button', { name: 'Read', exact: true }).click();
  await page.waitForFunction(() => document.querySelector('#ls5-period-ms')?.disabled === false, null, WAIT);
  // Table 9.2 defaults: period 0064 = 100 x 0.1 ms = 10 ms; discrete outputs "12".
  assert.equal(await page.inputValue('#ls5-period-ms'), '10');
  assert.equal(await page.inputValue('#ls5-discrete-outputs'), 'low-high');
  const legends = await page.$$eval('.ls5-page .panels:not(.ls5-outputs) .panel legend', (items) => items.map((item) => item.textContent));
  // The groups of §8.1–8.14 and §10, named in words.
  assert.deepEqual(legends, ['Serial interface', 'Measurement and output period', 'Exposure', 'Signal absence',
    'Pre-filtering', 'Preliminary result', 'Analog output', 'Discrete outputs', 'Triggering and latching', 'Ethernet']);
  // Table 9.2 "Measurement period (discrete – 0.1 ms, minimum value – 0.1 ms) ... 0001-FFFF".
  assert.match(await page.textContent('#ls5-period-ms-range'), /^0\.1 – 6553\.5 ms · address 06\/07/);
  // §8.10 limits "only in the range 0÷50000", shown in mm by formula 8.1 with the ID's range.
  assert.match(await page.textContent('#ls5-analog-upper-range'), /^0 – 50000 \(0 – 40\.001 mm\) · address 13\/14$/);
  // L73: the link settings are shown, not written (they change how the service reaches the sensor).
  assert.equal(await page.$eval('#ls5-baud-rate', (input) => input.disabled), true);
  await page.screenshot({ path: path.join(screenshots, 'ls5-page.png'), fullPage: true });
});

test('no select of the page is too narrow for its choices', async () => {
  // As on the ULS page: each select is at least as wide as the browser makes one with the same
  // choices left to its natural width (a hidden copy, same font), so its longest choice ("05 –
  // imparity control, 2 stop bits", table 9.2's latching modes) and so the one chosen show whole.
  const cut = await selectsTooNarrow(page, '.ls5-page select');
  assert.deepEqual(cut, []);
});

test('the §8 formulas of the page give the numbers of §8 and §9.5', async () => {
  // The page's module, bundled as the page gets it, run here (node) on numbers typed from the manual.
  const bundle = await esbuild.build({ entryPoints: ['src/ls5/ls5_outputs.ts'], bundle: true, format: 'esm', write: false });
  const outputsModule = await import(`data:text/javascript;base64,${Buffer.from(bundle.outputFiles[0].text).toString('base64')}`);
  const { analogOutput, ANALOG_RANGES, codeFromDistance, decodeDiscreteOutputs, discreteOutput, distanceMm, latchLimits } = outputsModule;
  const mA = ANALOG_RANGES['4-20mA'];
  // 8.1 distance = range · code / 50000: 40.001 mm, code 25000 -> 20.0005 mm.
  assert.equal(distanceMm(25000, 40.001), 20.0005);
  // 8.3, "for a 4-20 mA current output ... 4 mA ... 20 mA": limits 0 and 50000 (§9.5), K = 25000 -> 12 mA.
  assert.equal(analogOutput(mA, 0, 50000, 25000), 12);
  assert.equal(analogOutput(mA, 0, 50000, 0), 4);
  assert.equal(analogOutput(mA, 10000, 30000, 5000), 4);    // below K_n: A_min
  assert.equal(analogOutput(mA, 10000, 30000, 40000), 20);  // above K_v: A_max
  // "It is possible to invert the analog output (when K_v < K_n)": 4 + 16 · (12500 − 50000)/(0 − 50000) = 16 mA.
  assert.equal(analogOutput(mA, 50000, 0, 12500), 16);
  assert.equal(analogOutput(ANALOG_RANGES['0-10V'], 0, 50000, 10000), 2);  // 0-10 V: 10 · 10000/50000
  assert.equal(analogOutput(mA, 0, 50000, 65534), 4);  // §8.2 "the state of no result ... 4 mA" (L8)
  assert.equal(analogOutput(mA, 0, 50000, 65535, 40000), 20);  // no signal: the extreme nearer the last (L8)
  // 8.4 with table 9.3: "#01W1512": output 1 enabled, N = 0, swings 20000-40000; output 2 N = 1, 10000-30000.
  const [one, two] = decodeDiscreteOutputs('12');
  assert.deepEqual([one, two], [{ enabled: true, initial: 0 }, { enabled: true, initial: 1 }]);
  assert.equal(discreteOutput(one, 20000, 40000, 30000), 1);  // between the swings: not N
  assert.equal(discreteOutput(one, 20000, 40000, 10000), 0);  // below: N
  assert.equal(discreteOutput(one, 20000, 40000, 40000), 1);  // K_OC1 ≤ K ≤ K_OC2 includes the swing
  assert.equal(discreteOutput(two, 10000, 30000, 20000), 0);
  assert.equal(discreteOutput(two, 10000, 30000, 40000), 1);
  assert.equal(discreteOutput(two, 10000, 30000, 65535), 1);  // "In case of the signal loss ... the formula 8.4 is valid"
  assert.equal(discreteOutput(decodeDiscreteOutputs('02')[0], 0, 50000, 100), 0);  // "0 – the discrete output is disabled"
  // §8.14: "25000 - 10000/2 = 20000 = 4E20 (HEX) ... 25000 + 10000/2 = 30000 = 7530 (HEX)".
  assert.deepEqual(latchLimits(25000, 10000), { lower: 20000, upper: 30000 });
  assert.deepEqual(latchLimits(2000, 10000), { lower: 0, upper: 7000 });  // 8.6: "0, if int(K − D/2) < 0"
  // 8.5 with §8.14's welding example: "20 mm / 100 mm · 50000 = 10000".
  assert.equal(codeFromDistance(20, 100), 10000);
});

test('the analog and discrete indicators follow formulas 8.3 and 8.4 for the live code', async () => {
  // Defaults (table 9.2): analog limits 0000 and C350 (50000), 4-20 mA (the emulator's default
  // output without an ordering code, L74); discrete outputs 12 with swings 0 and 50000.
  assert.equal(await page.inputValue('#ls5-analog-type'), '4-20mA');
  // Read the indicators in the same turn as the check that the code lies in 0...50000: a live code
  // can be 65535 (no signal) a moment later, and then 8.3 holds an extreme instead (L8).
  const shown = await (await page.waitForFunction(() => {
    const analog = document.querySelector('#ls5-analog-value');
    if (!analog || !(Number(analog.dataset.code) <= 50000)) return null;
    return { code: Number(analog.dataset.code), value: Number(analog.dataset.value), text: analog.textContent,
      oc1: document.querySelector('#ls5-oc1').dataset.state, oc2: document.querySelector('#ls5-oc2').dataset.state };
  }, null, WAIT)).jsonValue();
  // 8.3 with K_n = 0, K_v = 50000: A = 4 + (20 − 4) · K / 50000.
  const expected = 4 + (16 * shown.code) / 50000;
  assert.ok(Math.abs(shown.value - expected) < 1e-9, `${shown.value} mA for K = ${shown.code}; 8.3 gives ${expected}`);
  assert.equal(shown.text, `${expected.toFixed(3)} mA`);
  // 8.4: every K of 0...50000 lies between the swings 0 and 50000: OC1 = not 0 = 1, OC2 = not 1 = 0.
  assert.deepEqual([shown.oc1, shown.oc2], ['1', '0']);
  await page.screenshot({ path: path.join(screenshots, 'ls5-page-outputs.png') });  // the top of the page
  // The 0-10 V output type turns the same code into volts: A = 10 · K / 50000.
  await page.selectOption('#ls5-analog-type', '0-10V');
  const volts = await (await page.waitForFunction(() => {
    const analog = document.querySelector('#ls5-analog-value');
    if (!/ V$/.test(analog.textContent) || !(Number(analog.dataset.code) <= 50000)) return null;
    return { code: Number(analog.dataset.code), value: Number(analog.dataset.value) };
  }, null, WAIT)).jsonValue();
  assert.ok(Math.abs(volts.value - (10 * volts.code) / 50000) < 1e-9, `${volts.value} V for K = ${volts.code}`);
  await page.selectOption('#ls5-analog-type', '4-20mA');
});

test('changing parameters on the page changes them in the emulator (its control socket)', async () => {
  assert.equal((await outputs()).analog_enabled, true);
  // Table 9.2 "Analog output is enabled/disabled: 00 – disabled", chosen and sent from the keyboard.
  await page.focus('#ls5-analog-output');
  await page.selectOption('#ls5-analog-output', 'disabled');
  await page.getByRole('button', { name: 'Upload Settings' }).focus();
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => /Uploaded and read back: analog-output/.test(document.querySelector('.ls5-page .panel-message').textContent),
    null, WAIT);
  assert.equal((await outputs()).analog_enabled, false);
  assert.equal(patches.length, 1);
  // Upper limit 25000 (table 9.2 13/14): the emulator's own output now follows 8.3 with K_v = 25000.
  await page.selectOption('#ls5-analog-output', 'enabled');
  await page.fill('#ls5-analog-upper', '25000');
  await page.getByRole('button', { name: 'Upload Settings' }).click();
  await page.waitForFunction(() => /Uploaded and read back: analog-output, analog-upper/.test(document.querySelector('.ls5-page .panel-message').textContent),
    null, WAIT);
  assert.equal(patches.length, 2);
  assert.equal(await page.textContent('[data-mm-for="analog-upper"]'), '= 20.0005 mm');  // 8.1
  // The emulator's output at a result of its own: 4 + 16 · K / 25000 below 25000, 20 mA above.
  let device;
  for (let tries = 0; tries < 50; ++tries) {
    device = await outputs();
    if (device.result <= 50000 && device.analog_enabled) break;
  }
  assert.equal(device.analog_enabled, true);
  assert.equal(device.unit, 'mA');
  const expected = device.result >= 25000 ? 20 : 4 + (16 * device.result) / 25000;
  assert.ok(Math.abs(device.analog - expected) < 1e-6, `emulator ${device.analog} mA at K = ${device.result}`);
  await page.waitForFunction(() => /K_v = 25000/.test(document.querySelector('.ls5-outputs .hint').textContent), null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'ls5-page-uploaded.png'), fullPage: true });
});

test('an out-of-range value shows the error and sends nothing', async () => {
  const before = patches.length;
  // §8.10: "The values of the lower and upper bounds can only be in the range 0÷50000".
  await page.fill('#ls5-analog-upper', '50001');
  await page.waitForFunction(() => document.querySelector('#ls5-analog-upper').getAttribute('aria-invalid') === 'true', null, WAIT);
  assert.match(await page.textContent('#ls5-analog-upper-problem'), /50001 is out of range: 0 – 50000/);
  // Table 9.2 0D: "must be odd: m = 2h + 1".
  await page.fill('#ls5-median-points', '4');
  assert.match(await page.textContent('#ls5-median-points-problem'), /4 is not odd/);
  // Table 9.2 06/07: "discrete – 0.1 ms".
  await page.fill('#ls5-period-ms', '1.25');
  assert.match(await page.textContent('#ls5-period-ms-problem'), /1\.25 is not a multiple of 0\.1 ms/);
  // §8.11: "The first swing of the discrete output must be less than (or equal to) the second swing".
  await page.fill('#ls5-output1-first-swing', '45000');
  await page.fill('#ls5-output1-second-swing', '40000');
  assert.equal(await page.textContent('#ls5-output1-second-swing-problem'),
    'the first swing (45000) must not be above the second (40000)');
  await page.getByRole('button', { name: 'Upload Settings' }).click();
  await page.waitForFunction(() => /^Nothing sent: /.test(document.querySelector('.ls5-page .panel-message').textContent), null, WAIT);
  assert.equal(patches.length, before);  // no request left the page
  assert.equal(await page.evaluate(() => document.activeElement.id), 'ls5-period-ms');  // the first field at fault
  await page.screenshot({ path: path.join(screenshots, 'ls5-page-out-of-range.png'), fullPage: true });
  // Read shows the sensor's values again: nothing reached it.
  await page.getByRole('button', { name: 'Read', exact: true }).click();
  await page.waitForFunction(() => document.querySelector('#ls5-analog-upper').value === '25000' &&
    document.querySelector('#ls5-median-points').value === '5', null, WAIT);
  assert.equal(await page.inputValue('#ls5-period-ms'), '10');
  assert.equal(await page.inputValue('#ls5-output1-first-swing'), '0');
  assert.equal(await panelMessage(), '');  // the refusal went with the edits it was about
});

test('Latch (FX) and Read latched (FR) latch in the emulator (table 9.1, L75)', async () => {
  assert.match(await page.textContent('#ls5-latch-mode'), /^Latching 01: FX records the result in the latch only/);
  await page.getByRole('button', { name: 'Latch (FX)' }).click();
  await page.waitForFunction(() => /code \d+/.test(document.querySelector('#ls5-latched').textContent), null, WAIT);
  const latched = Number(/code (\d+)/.exec(await page.textContent('#ls5-latched'))[1]);
  assert.equal((await outputs()).latched, latched);
  await page.getByRole('button', { name: 'Read latched (FR)' }).click();
  await page.waitForFunction(() => /Read latched \(FR\): done/.test(document.querySelector('.ls5-page .page-message').textContent), null, WAIT);
  assert.equal(Number(/code (\d+)/.exec(await page.textContent('#ls5-latched'))[1]), latched);
});

test('every control has a label and Tab reaches every writable field', async () => {
  const unlabelled = await page.$$eval('input, select, textarea, button, meter', (controls) =>
    controls.filter((control) => !(control.labels?.length || control.getAttribute('aria-label') ||
      (control.tagName === 'BUTTON' && control.textContent.trim())))
      .map((control) => control.outerHTML));
  assert.deepEqual(unlabelled, []);
  const fields = await page.$$eval('.ls5-page [data-setting]', (inputs) => inputs.filter((input) => !input.disabled).map((input) => input.id));
  assert.ok(fields.length > 20, fields.join(' '));
  await page.focus(`#${fields[0]}`);
  const reached = [fields[0]];
  for (let step = 1; step < fields.length; ++step) {
    await page.keyboard.press('Tab');
    reached.push(await page.evaluate(() => document.activeElement.id));
  }
  assert.deepEqual(reached, fields);
  await page.focus('#ls5-pre-filter');
  await page.keyboard.press('ArrowDown');
  assert.equal(await page.inputValue('#ls5-pre-filter'), 'median');
  await page.waitForFunction(() => document.querySelector('#ls5-pre-filter').closest('.field').classList.contains('changed'), null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'ls5-page-keyboard.png') });
});

test('the page names the manual\'s sections once, in its foot, and says everything else in words', async () => {
  // With the parameters read, the outputs computed and a result latched: every text of the page is shown.
  assert.match(await page.textContent('#ls5-latched'), /code \d+/);
  assert.equal(await page.textContent('#sensor-view > footer.document-sections'), 'LS5 manual: §5 ordering code, §8 protocol and formulas, table 9.1 commands, table 9.2 parameters, ' +
    '§10 Ethernet; docs/conformance.md.');
  assert.deepEqual(await sectionsOutsideFoot(page), []);
});

test('an LS5 heard over UDP only shows its stream and why it has no parameters (§10)', async () => {
  await page.goto(`${url}#/sensor/belt-udp`);
  await page.waitForFunction(() => {
    const plot = document.querySelector('.ls5-page .live-plot');
    return Number(plot?.dataset.points) > 500 && plot.dataset.drawnEnd !== undefined;  // several packets of 168 (§10)
  }, null, WAIT);
  assert.match(await page.textContent('[data-id="udp"]'), /^127\.0\.0\.1:\d+$/);
  assert.equal(await page.textContent('.ls5-page .panel-message'), 'An LS5 heard over UDP only (its manual: "The ' +
    'Ethernet interface is only used for the one-way transmission of the measurement stream"): its parameters ' +
    'need its serial port in the site file.');
  assert.deepEqual(await sectionsOutsideFoot(page), []);
  await page.screenshot({ path: path.join(screenshots, 'ls5-page-udp.png'), fullPage: true });
});

test('the family\'s actions the page does not place itself come from GET /api/families: Reset (DF)', async () => {
  await page.goto(`${url}#/sensor/belt`);
  await page.waitForSelector('.ls5-page .other-actions button[data-action="reset"]', WAIT);
  assert.deepEqual(await page.$$eval('.ls5-page .other-actions button', (buttons) => buttons.map((b) => [b.textContent, b.title])),
    [['Reset', 'every parameter to its default (DF)']]);
  // A parameter away from its default (table 9.2, 03: analog output, default enabled), then DF.
  const patched = await fetch(`${url}api/sensors/belt/settings`, {
    method: 'PATCH', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ 'analog-output': 'disabled' }),
  });
  assert.equal(patched.status, 200, await patched.text());
  assert.equal((await outputs()).analog_enabled, false);
  await page.click('.ls5-page .other-actions button[data-action="reset"]');
  await page.waitForFunction(() => document.querySelector('.ls5-page .page-message')?.textContent === 'Reset: done.', null, WAIT);
  assert.equal((await outputs()).analog_enabled, true);
});

test('the page raised no script error or policy violation', () => {
  assert.deepEqual(pageErrors, []);
});
