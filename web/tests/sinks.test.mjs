// Browser test of the historians on the overview: `rangekit serve --demo` with an influx sink
// on a loopback port no one listens on, so every write is refused and the readings wait in the
// spool; the page shows the sink down and how far behind. Run by ctest (browser.sinks).
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import net from 'node:net';
import path from 'node:path';
import { after, before, test } from 'node:test';
import { cli, launch, screenshots, stopped, WAIT, waitForLine, watchErrors } from './support.mjs';

let serve;
let browser;
let page;
let pageErrors;
let sinkUrl;

// A loopback port bound and closed again: nothing listens there.
function closedPort() {
  return new Promise((resolve, reject) => {
    const server = net.createServer();
    server.once('error', reject);
    server.listen(0, '127.0.0.1', () => {
      const { port } = server.address();
      server.close(() => resolve(port));
    });
  });
}

before(async () => {
  const port = await closedPort();
  sinkUrl = `http://127.0.0.1:${port}/write`;
  serve = spawn(cli, ['serve', '--demo', '--listen', '127.0.0.1:0', '--sink', `influx+${sinkUrl}`],
    { stdio: ['ignore', 'pipe', 'inherit'] });
  serve.stdout.setEncoding('utf8');
  const url = await waitForLine(serve, /dashboard: (http:\/\/\S+)/, 'dashboard address');
  serve.stdout.resume();  // the service's lines, not needed
  browser = await launch();
  page = await browser.newPage({ viewport: { width: 1400, height: 720 } });
  pageErrors = watchErrors(page);
  await page.goto(url);
});

after(async () => {
  await browser?.close();
  await stopped(serve);
});

const sink = () => `.sink[data-url="${sinkUrl}"]`;

test('a sink whose historian refuses the connection shows down, with the rows waiting and their age', async () => {
  await page.waitForFunction((selector) => document.querySelector(selector)?.dataset.state === 'down', sink(), WAIT);
  assert.equal(await page.isVisible('#sinks'), true);
  assert.equal(await page.textContent(`${sink()} .sink-kind`), 'INFLUX');
  assert.equal(await page.textContent(`${sink()} .sink-state`), 'Down');
  assert.notEqual((await page.textContent(`${sink()} .sink-error`)).trim(), '');
  // The demo's sensors go on reading: the spool grows and the oldest row ages.
  const behind = `${sink()} .sink-behind`;
  const waiting = () => page.$eval(behind, (element) => element.textContent);
  await page.waitForSelector(behind, { timeout: WAIT.timeout });
  const first = await waiting();
  assert.match(first, /^[\d.]+ (s|min).* behind · [\d,]+ rows? waiting$/);
  await page.waitForFunction(([selector, was]) => {
    const rows = (text) => Number(text.match(/([\d,]+) rows? waiting/)[1].replaceAll(',', ''));
    return rows(document.querySelector(selector).textContent) > rows(was);
  }, [behind, first], WAIT);
  await page.waitForFunction(() => / 1 historian down/.test(document.getElementById('summary').textContent),
    null, WAIT);
  await page.screenshot({ path: path.join(screenshots, 'sink-down.png') });
});

test('the page raised no script error or policy violation', () => {
  assert.deepEqual(pageErrors, []);
});
