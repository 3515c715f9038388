// What the browser tests share: the browser (Debian's chromium, or skip), the rangekit
// binary, the screenshot folder, and child processes read and stopped.
import { existsSync, mkdirSync, readdirSync, readFileSync } from 'node:fs';
import { spawn } from 'node:child_process';
import net from 'node:net';
import path from 'node:path';
import { chromium } from 'playwright-core';

export const browserPath = process.env.RANGEKIT_CHROMIUM ?? '/usr/bin/chromium';
if (!existsSync(browserPath)) {
  console.log(`SKIPPED: no browser at ${browserPath}; \`bash scripts/install-deps.sh test\` installs Debian's chromium`);
  process.exit(77);  // ctest: SKIP_RETURN_CODE
}
export const cli = process.env.RANGEKIT_CLI;
if (!cli || !existsSync(cli)) throw new Error(`RANGEKIT_CLI (${cli}) is not the rangekit binary`);
export const screenshots = process.env.RANGEKIT_SCREENSHOTS ?? path.resolve('screenshots');
mkdirSync(screenshots, { recursive: true });

export const START_TIMEOUT = 120_000;
// Every wait is on a condition of the page; the timeout only ends a test that went wrong.
export const WAIT = { timeout: 60_000, polling: 100 };

export function launch(extraArgs = []) {
  return chromium.launch({
    executablePath: browserPath,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage', ...extraArgs],
  });
}

// Reads the child's stdout (setEncoding done) until `pattern` matches; its first group.
export function waitForLine(child, pattern, what) {
  return new Promise((resolve, reject) => {
    let text = '';
    const timer = setTimeout(() => reject(new Error(`no ${what} within ${START_TIMEOUT} ms:\n${text}`)), START_TIMEOUT);
    const onData = (chunk) => {
      text += chunk;
      const match = text.match(pattern);
      if (match) {
        clearTimeout(timer);
        child.stdout.off('data', onData);
        resolve(match[1]);
      }
    };
    child.stdout.on('data', onData);
    child.once('exit', (code) => reject(new Error(`${what}: the process exited (${code}) first:\n${text}`)));
  });
}

// SIGTERM, then waits for the exit.
export function stopped(child) {
  return new Promise((resolve) => {
    if (!child || child.exitCode !== null || child.signalCode !== null) return resolve();
    child.once('exit', () => resolve());
    child.kill('SIGTERM');
  });
}

// Collects script errors and console errors (content-security violations among them).
export function watchErrors(page) {
  const errors = [];
  page.on('pageerror', (error) => errors.push(String(error)));
  page.on('console', (message) => {
    if (message.type() === 'error') errors.push(message.text());
  });
  return errors;
}

// One request to an emulator's control socket (docs/emulator-uls.md, docs/emulator-ls5.md,
// "Control"): its one-line JSON answer. Tests check the emulator through it, not the page.
export function controlRequest(socketPath, request) {
  return new Promise((resolve, reject) => {
    const socket = net.createConnection(socketPath);
    let text = '';
    socket.setEncoding('utf8');
    socket.on('connect', () => socket.write(`${JSON.stringify(request)}\n`));
    socket.on('data', (chunk) => {
      text += chunk;
      if (text.includes('\n')) {
        socket.end();
        resolve(JSON.parse(text.slice(0, text.indexOf('\n'))));
      }
    });
    socket.on('error', reject);
  });
}

// The demo's emulator process serving `port` (its pty link), found by its command line.
export function emulatorOn(port) {
  for (const entry of readdirSync('/proc')) {
    if (!/^\d+$/.test(entry)) continue;
    let args;
    try {
      args = readFileSync(`/proc/${entry}/cmdline`, 'utf8').split('\0').filter(Boolean);
    } catch {
      continue;  // gone meanwhile
    }
    const at = args.indexOf('--port');
    if (args[1] === 'sim' && at > 0 && args[at + 1] === port) return { pid: Number(entry), args };
  }
  throw new Error(`no emulator process serves ${port}`);
}

// The same emulator again on the same pty link, as the service met it before a kill -9 (its
// control socket left out: the killed one's file remains). Stop it with stopped().
export function restartEmulator(emulator) {
  const args = emulator.args.slice(1);
  const control = args.indexOf('--control');
  if (control >= 0) args.splice(control, 2);
  return spawn(cli, args, { stdio: 'ignore' });
}

// The selects under `selector` narrower than the browser makes one with the same choices left
// to its natural width (a hidden copy, same font): each as "id: W px < N px". Empty when every
// select shows its longest choice, and so the one chosen, whole.
export function selectsTooNarrow(page, selector) {
  return page.$$eval(selector, (selects) => selects.flatMap((select) => {
    const copy = select.cloneNode(true);
    copy.removeAttribute('id');
    copy.style.cssText = 'position: absolute; visibility: hidden; width: auto; min-width: 0; max-width: none;';
    select.parentElement.append(copy);
    const natural = copy.getBoundingClientRect().width;
    copy.remove();
    const width = select.getBoundingClientRect().width;
    return width + 0.5 < natural ? [`${select.id}: ${width.toFixed(0)} px < ${natural.toFixed(0)} px`] : [];
  }));
}

// Where the open sensor page cites a section of its document outside its foot: each text or
// title, aria-label or placeholder (hidden ones too, as tooltips and screen readers show them)
// with "§", "table 9.2" or "formula 8.3", as "tag: text". Empty when the page says it in words.
export function sectionsOutsideFoot(page) {
  return page.$eval('#sensor-view', (view) => {
    const citing = /§|\b(table|formulas?) \d+\.\d/i;
    const found = [];
    for (const node of view.querySelectorAll('*')) {
      if (node.closest('.document-sections')) continue;
      const own = [...node.childNodes].filter((child) => child.nodeType === Node.TEXT_NODE).map((child) => child.data).join('');
      for (const text of [own, ...['title', 'aria-label', 'placeholder'].map((name) => node.getAttribute(name) ?? '')]) {
        if (citing.test(text)) found.push(`${node.tagName.toLowerCase()}: ${text.trim()}`);
      }
    }
    return found;
  });
}
