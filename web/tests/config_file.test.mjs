// Browser test of the ULS page's configuration files (U104): Save, then Open puts a changed
// setting back (checked on the emulator's control socket); a corrupt file shows its line, key
// and range and nothing reaches the unit. Screenshots in RANGEKIT_SCREENSHOTS.
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { WAIT, cli, controlRequest, launch, screenshots, stopped, waitForLine, watchErrors } from './support.mjs';

let serve;
let url;
let demoDir;
let browser;
let page;
let pageErrors;
let saved;  // the text of the file Save downloaded
const files = mkdtempSync(path.join(os.tmpdir(), 'rangekit-config-file-'));

// One request to the demo bus emulator's control socket (docs/emulator-uls.md, "Control").
const control = (request) => controlRequest(path.join(demoDir, 'bus.control'), request);

const prfOfUnit = async (unit) => (await control({ cmd: 'outputs', device: unit })).prf_hz;
const status = () => page.textContent('.config-status');

// Opens `text` as the file `name` with the page's Open Configuration; waits for the page's answer.
async function open(name, text) {
  const file = path.join(files, name);
  writeFileSync(file, text);
  await page.setInputFiles('#config-open-bay-C', file);
  await page.waitForFunction(() => /^(Opened|Nothing sent|Upload failed|Open failed)/
    .test(document.querySelector('.config-status').textContent), null, WAIT);
  return status();
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
  page = await browser.newPage({ viewport: { width: 1400, height: 1000 }, acceptDownloads: true });
  pageErrors = watchErrors(page);
  await page.goto(`${url}#/sensor/bay-C`);
  await page.waitForSelector('.config-file', WAIT);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
  rmSync(files, { recursive: true, force: true });
});

// §2: "the File Menu includes options that allow you to store this information as a configuration
// file (*.uls) ... Whenever you open a stored configuration file, always remember to Upload Settings."
test('U104: Save downloads the settings; Open of that file puts a changed setting back', async () => {
  assert.deepEqual(await prfOfUnit('C'), [2000, 2000, 2000]);  // §2's screen: "PRF 2000 Hz"
  const [download] = await Promise.all([
    page.waitForEvent('download', { timeout: WAIT.timeout }),
    page.getByRole('button', { name: 'Save Configuration' }).click(),
  ]);
  assert.equal(download.suggestedFilename(), 'bay-C.toml');
  saved = readFileSync(await download.path(), 'utf8');
  // The TOML of `rangekit uls config save` (docs/cli.md): [settings], keys as `rangekit uls get` names them.
  assert.match(saved, /^\[settings\]$/m);
  assert.match(saved, /^prf-hz = \[2000, 2000, 2000\]/m);
  await page.waitForFunction(() => /^Saved bay-C\.toml/.test(document.querySelector('.config-status').textContent),
    null, WAIT);

  // Changed behind the page's back: through the service's API, not the page.
  const patched = await fetch(`${url}api/sensors/bay-C/settings`, {
    method: 'PATCH',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ 'prf-hz': [1000, 2500, 3000] }),
  });
  assert.equal(patched.status, 200, await patched.text());
  assert.deepEqual(await prfOfUnit('C'), [1000, 2500, 3000]);

  assert.match(await open('bay-C.toml', saved), /^Opened bay-C\.toml: every setting uploaded, read back and verified/);
  assert.deepEqual(await prfOfUnit('C'), [2000, 2000, 2000]);  // §8 $PF,a,b,c, read from the emulator
  // The panels show what was read back.
  assert.equal(await page.inputValue('#setting-prf-hz'), '2000,2000,2000');
  await page.screenshot({ path: path.join(screenshots, 'config-file-opened.png'), fullPage: true });
});

test('U104: a bad file shows its line, key and range, and nothing reaches the unit', async () => {
  assert.ok(saved, 'the first test saved a file');
  // A valid PRF change before the bad value: had anything been sent, the PRF would change.
  const lines = saved.split('\n').map((line) => line.replace(/^prf-hz = .*/, 'prf-hz = [3000, 3000, 3000]')
    .replace(/^short-gate-m = .*/, 'short-gate-m = 5000.0'));
  const gateLine = lines.findIndex((line) => line.startsWith('short-gate-m =')) + 1;
  assert.ok(lines.findIndex((line) => line.startsWith('prf-hz =')) + 1 < gateLine);
  // §8 Set/Get Short Gate "0-1700 m" (U18).
  assert.equal(await open('out-of-range.toml', lines.join('\n')),
    `Nothing sent: out-of-range.toml:${gateLine}: 'short-gate-m' is outside the allowed values: 0..1700 metres`);
  assert.equal(await page.getAttribute('.config-status', 'data-state'), 'error');
  assert.deepEqual(await prfOfUnit('C'), [2000, 2000, 2000]);
  await page.screenshot({ path: path.join(screenshots, 'config-file-refused.png'), fullPage: true });

  // Not TOML at all.
  assert.match(await open('corrupt.toml', '[settings]\nprf = [3000, 3000\nmode = "binning"\n'),
    /^Nothing sent: corrupt\.toml:3: /);
  // §8 Set/Get Measurement Mode: averaging, binning, look down only.
  assert.match(await open('bad-mode.toml', '[settings]\nprf = [3000, 3000, 3000]\nmode = "sideways"\n'),
    /^Nothing sent: bad-mode\.toml:3: 'mode' must be one of: averaging \(1\), binning \(2\), look-down \(3\)/);
  assert.deepEqual(await prfOfUnit('C'), [2000, 2000, 2000]);
});

test('the file controls are labelled and reached from the keyboard', async () => {
  const unlabelled = await page.$$eval('.config-file input, .config-file button', (controls) =>
    controls.filter((control) => !(control.labels?.length || (control.tagName === 'BUTTON' && control.textContent.trim())))
      .map((control) => control.outerHTML));
  assert.deepEqual(unlabelled, []);
  await page.getByRole('button', { name: 'Save Configuration' }).focus();
  await page.keyboard.press('Tab');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'config-open-bay-C');
});

test('the page raised no script error or policy violation', () => {
  // The refused uploads answer 400 (docs/api.md), which chromium logs.
  const unexpected = pageErrors.filter((error) => !/status of 400 \(Bad Request\)/.test(error));
  assert.deepEqual(unexpected, []);
});
