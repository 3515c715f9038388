// Keystroke response on the overview for the site bench (site.bench.mjs): from a key's keydown
// to the first frame after the cards shown match the filter and the problem-only choice.
import { sleep } from './bench_frames.mjs';

// Installed in the page once: keydown takes the event's own time stamp (when the browser got the
// key, so time queued behind the page's work counts); after the filter's input or the checkbox's change, each animation frame checks the
// cards until the shown ones are the expected ones, then a task after that frame (so its
// style, layout and paint are included) takes the time.
export function watchKeystrokes(page) {
  return page.evaluate(() => {
    window.__keystrokes = [];
    let pressed = null;
    const filter = document.getElementById('filter');
    const problems = document.getElementById('problems');
    const problem = (card) => card.dataset.connected !== 'true' || card.querySelector('.stats .bad') !== null;
    const settled = () => {
      const text = filter.value.trim().toLowerCase();
      return [...document.querySelectorAll('.card')].every((card) =>
        card.hidden === !(card.dataset.sensor.toLowerCase().includes(text) && (!problems.checked || problem(card))));
    };
    document.addEventListener('keydown', (event) => { pressed = event.timeStamp; }, true);
    const answered = () => {
      const start = pressed;
      pressed = null;
      if (start === null) return;
      const check = () => {
        if (!settled()) return requestAnimationFrame(check);
        setTimeout(() => window.__keystrokes.push({
          ms: performance.now() - start,
          shown: document.querySelectorAll('.card:not([hidden])').length,
        }), 0);
      };
      requestAnimationFrame(check);
    };
    filter.addEventListener('input', answered);
    problems.addEventListener('change', answered);
  });
}

// Types `text` into the filter and takes it back with Backspace, then toggles the problem-only
// checkbox on and off with Space, `rounds` times (the last digit of `text` cycles 0-9), a
// pause of 150-400 ms between keys, as a person types. Each key's response in ms, by kind.
export async function pressKeys(page, text, rounds) {
  const filterMs = [];
  const problemsMs = [];
  let problemsShown = 0;
  for (let round = 0; round < rounds; round++) {
    const typed = text.replace(/\d$/, String(round % 10));
    await page.focus('#filter');
    for (const key of [...typed, ...[...typed].map(() => 'Backspace')]) filterMs.push(await press(page, key));
    await page.focus('#problems');
    for (const on of [true, false]) {
      const ms = await press(page, 'Space');
      problemsMs.push(ms);
      if (on) problemsShown = await page.evaluate(() => window.__keystrokes.at(-1).shown);
    }
  }
  return { filterMs, problemsMs, problemsShown };
}

async function press(page, key) {
  const count = await page.evaluate(() => window.__keystrokes.length);
  await page.keyboard.press(key);
  await page.waitForFunction((before) => window.__keystrokes.length > before, count, { timeout: 30_000, polling: 20 });
  const ms = await page.evaluate(() => window.__keystrokes.at(-1).ms);
  await sleep(150 + Math.random() * 250);
  return ms;
}

// p50, p99 and the largest of a list of milliseconds.
export function percentiles(values) {
  const sorted = [...values].sort((a, b) => a - b);
  const at = (q) => sorted[Math.min(sorted.length - 1, Math.ceil(q * sorted.length) - 1)];
  return { p50: at(0.5), p99: at(0.99), max: sorted[sorted.length - 1], count: sorted.length };
}
