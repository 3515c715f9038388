// Browser test of the ULS page's RS-485 Network window on the demo's bus (U105, U106): Scan
// lists the units that answer; Assign refuses an address in use and moves a unit to a free
// one, checked on the bus emulator's control socket. Screenshots in RANGEKIT_SCREENSHOTS.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import path from 'node:path';
import { after, before, test } from 'node:test';
import {
  WAIT, cli, controlRequest, launch, screenshots, sectionsOutsideFoot, stopped, waitForLine, watchErrors,
} from './support.mjs';

let serve;
let url;
let demoDir;
let browser;
let page;
let pageErrors;

// One request to the demo bus emulator's control socket (docs/emulator-uls.md, "Control").
const control = (request) => controlRequest(path.join(demoDir, 'bus.control'), request);

// Whether the emulator holds a unit at `address` now (its control socket routes by address).
const unitAt = async (address) => !('error' in await control({ cmd: 'outputs', device: address }));
const optionText = (address) => page.$eval(`#rs485-select-bay-C option[value="${address}"]`, (option) => option.textContent);
const warning = () => page.textContent('.rs485 .hint[role="status"]');

async function scan() {
  await page.getByRole('button', { name: 'Scan the Bus' }).click();
  await page.waitForFunction(() => /answered of \d+ addresses/.test(document.querySelector('.rs485-status').textContent),
    null, WAIT);
  return page.$$eval('.rs485-units tr.unit', (rows) => rows.map((row) =>
    [...row.querySelectorAll('td')].slice(0, 3).map((cell, index) => (index === 1 ? cell.textContent !== '' : cell.textContent))));
}

async function assign(to) {
  await page.selectOption('#rs485-select-bay-C', to);
  await page.getByRole('button', { name: 'Assign', exact: true }).click();
  await page.waitForFunction(() => /^(Assign refused|The unit at|Assign failed)/
    .test(document.querySelector('.rs485 .hint[role="status"]').textContent), null, WAIT);
  return warning();
}

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
  await page.goto(`${url}#/sensor/bay-C`);
  await page.waitForSelector('#rs485-select-bay-C', WAIT);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
});

// §7: "Values with an asterisk have already been assigned in the network using the ULS program."
test('U105: the addresses of the site file on this bus are marked with an asterisk', async () => {
  assert.equal(await page.textContent('.rs485-current'), 'C');  // §7 "Current address:"
  await page.waitForFunction(() => document.querySelector('#rs485-select-bay-C option[value="A"]')?.textContent.includes('*'),
    null, WAIT);
  assert.equal(await optionText('A'), 'A * (bay-A)');
  assert.equal(await optionText('D'), 'D * (bay-D)');
  assert.equal(await optionText('E'), 'E');
  // §8 Set/Get Unit Address: "a-z, A-Z, or 0-9": 62 addresses.
  assert.equal(await page.$$eval('#rs485-select-bay-C option', (options) => options.length), 62);
});

test('U105: Scan lists the units that answer on the bus', async () => {
  assert.deepEqual(await scan(), [['A', true, 'bay-A'], ['B', true, 'bay-B'], ['C', true, 'bay-C'], ['D', true, 'bay-D']]);
  assert.match(await page.textContent('.rs485-status'), /^4 units answered of 62 addresses asked on /);
  await page.screenshot({ path: path.join(screenshots, 'rs485-scan.png'), fullPage: true });
});

// §7: "The RS485 system will not function correctly with same address assigned to 2 or more units."
test('U105: Assign refuses an address a unit answers at, and nothing changes', async () => {
  assert.match(await assign('A'), /^Assign refused: address 'A' is already in use on the bus/);
  assert.ok(await unitAt('C'));
  assert.equal(await page.textContent('.rs485-current'), 'C');
  await page.screenshot({ path: path.join(screenshots, 'rs485-refused.png'), fullPage: true });
});

test('U106: Assign moves the unit to a free address; the site file keeps naming the old one', async () => {
  assert.equal(await unitAt('E'), false);
  assert.match(await assign('E'), /^The unit at C now answers at E\. The site file still names bay-C at address C/);
  assert.ok(await unitAt('E'));  // the emulator's unit C answers at E now
  assert.equal(await unitAt('C'), false);
  assert.equal(await page.textContent('.rs485-current'), 'E (the site file says C)');
  assert.deepEqual(await scan(), [['A', true, 'bay-A'], ['B', true, 'bay-B'], ['D', true, 'bay-D'],
    ['E', true, 'not in the site file']]);
  assert.match(await page.textContent('.rs485-status'), /silent: C \(bay-C\)\.$/);
  assert.equal(await optionText('E'), 'E * (answers)');
  await page.screenshot({ path: path.join(screenshots, 'rs485-assigned.png'), fullPage: true });
  // And back, from the keyboard: the select, then Assign.
  await page.focus('#rs485-select-bay-C');
  await page.selectOption('#rs485-select-bay-C', 'C');
  await page.keyboard.press('Tab');
  assert.equal(await page.evaluate(() => document.activeElement.textContent), 'Assign');
  await page.keyboard.press('Enter');
  await page.waitForFunction(() => /answers at C again/.test(document.querySelector('.rs485 .hint[role="status"]').textContent),
    null, WAIT);
  assert.ok(await unitAt('C'));
  assert.equal(await unitAt('E'), false);
});

test('a ULS alone on its port says the network is for bus units', async () => {
  await page.evaluate(() => { location.hash = '#/sensor/silo'; });
  await page.waitForFunction(() => /alone on its port/.test(document.querySelector('.sensor-page[data-sensor="silo"] .rs485')?.textContent ?? ''),
    null, WAIT);
  assert.equal(await page.textContent('.sensor-page[data-sensor="silo"] .rs485 .hint'), 'silo is alone on its port (the $ ' +
    'protocol; no address in the site file): the RS-485 network is for units addressed on a bus.');
  assert.deepEqual(await sectionsOutsideFoot(page), []);
  const refused = await fetch(`${url}api/sensors/silo/bus/scan`, { method: 'POST' });
  assert.equal(refused.status, 409);
});

test('the network controls are labelled', async () => {
  await page.evaluate(() => { location.hash = '#/sensor/bay-C'; });
  await page.waitForSelector('#rs485-select-bay-C', WAIT);
  const unlabelled = await page.$$eval('.rs485 select, .rs485 button', (controls) =>
    controls.filter((control) => !(control.labels?.length || (control.tagName === 'BUTTON' && control.textContent.trim())))
      .map((control) => control.outerHTML));
  assert.deepEqual(unlabelled, []);
});

test('the page raised no script error or policy violation', () => {
  // The refused assign answers 400 (docs/api.md), which chromium logs.
  const unexpected = pageErrors.filter((error) => !/status of 400 \(Bad Request\)/.test(error));
  assert.deepEqual(unexpected, []);
});
