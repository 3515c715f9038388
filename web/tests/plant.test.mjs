// A plant view: 30 ULS units on three RS-485 buses fit a 1920 x 1080 page without scrolling,
// every card connected and every sparkline still growing after all have been seen live.
import assert from 'node:assert/strict';
import { execFileSync, spawn } from 'node:child_process';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { cli, launch, screenshots, stopped, WAIT, waitForLine, watchErrors } from './support.mjs';

const BUSES = 3;
const UNITS = 'ABCDEFGHIJ';
const SENSORS = BUSES * UNITS.length;

const dir = mkdtempSync(path.join(tmpdir(), 'rangekit-plant-'));
const emulators = [];
let serve;
let browser;
let page;
let pageErrors;

before(async () => {
  // Every unit of a bus sees the same level rising and falling (the bus emulator's one scene).
  writeFileSync(path.join(dir, 'scene.toml'),
    '[[targets]]\nname = "level"\npath = [[0, 30], [30, 8], [60, 30]]\nrepeat = true\nreflectivity = 0.5\n');
  let site = '[service]\ncapture_dir = "captures"\n';
  for (let bus = 1; bus <= BUSES; bus++) {
    const port = path.join(dir, `bus${bus}`);
    const addresses = [...UNITS].flatMap((unit) => ['--address', unit]);
    const emulator = spawn(cli, ['sim', 'uls', '--bus', port, ...addresses, '--scene', path.join(dir, 'scene.toml')],
      { stdio: ['ignore', 'pipe', 'inherit'] });
    emulator.stdout.setEncoding('utf8');
    emulators.push(emulator);
    await waitForLine(emulator, /(ready)/, `bus ${bus} emulator`);
    emulator.stdout.resume();
    for (const unit of UNITS) {
      // §7: "The Continuous Output setting must be turned off since units only talk on the bus when addressed."
      execFileSync(cli, ['uls', 'set', '--port', port, '--address', unit, 'continuous=off'], { stdio: 'ignore' });
      site += `[[sensor]]\nname = "line${bus}-${unit}"\nfamily = "uls"\nport = "${port}"\naddress = "${unit}"\n`;
    }
  }
  writeFileSync(path.join(dir, 'site.toml'), site);
  serve = spawn(cli, ['serve', '--config', path.join(dir, 'site.toml'), '--listen', '127.0.0.1:0'],
    { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const url = await waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  serve.stdout.resume();
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1920, height: 1080 } });
  pageErrors = watchErrors(page);
  await page.goto(url);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
  for (const emulator of emulators) await stopped(emulator);
  rmSync(dir, { recursive: true, force: true });
});

test('30 sensors fit on a 1920 x 1080 screen and stay live', async () => {
  await page.waitForFunction((count) => {
    const cards = [...document.querySelectorAll('.card')];
    return cards.length === count &&
      cards.every((card) => card.dataset.connected === 'true' && card.dataset.reading === 'live');
  }, SENSORS, WAIT);
  const layout = await page.evaluate(() => ({
    scroll: document.documentElement.scrollHeight - window.innerHeight,
    outside: [...document.querySelectorAll('.card')]
      .filter((card) => card.getBoundingClientRect().bottom > window.innerHeight ||
        card.getBoundingClientRect().right > window.innerWidth)
      .map((card) => card.dataset.sensor),
  }));
  assert.deepEqual(layout.outside, []);
  assert.ok(layout.scroll <= 0, `the page scrolls by ${layout.scroll} px`);
  // Still live: every card's sparkline gets new points after this moment.
  const points = await page.$$eval('.card', (cards) => cards.map((card) => Number(card.dataset.points)));
  await page.waitForFunction((before) =>
    [...document.querySelectorAll('.card')].every((card, i) => Number(card.dataset.points) > before[i] + 4),
    points, WAIT);
  await page.waitForFunction(() => [...document.querySelectorAll('.card')].every(
    (card) => Number(card.dataset.points) >= 24), null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'plant-30-sensors.png') });
  assert.deepEqual(pageErrors, []);
});
