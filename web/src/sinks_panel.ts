// The historians on the overview (GET /api/sinks, docs/sinks.md): each sink up or down, and
// when down or catching up how far behind it is. A service without sinks shows nothing.
import type { Sink } from './api';

// Rows wait up to a batch's 100 ms in normal work; older than this, the sink is behind.
const BEHIND_S = 2;

const countFormat = new Intl.NumberFormat('en');
const secondsFormat = new Intl.NumberFormat('en', { maximumFractionDigits: 1, minimumFractionDigits: 1 });

// "4.2 s", "3 min 12 s", "2 h 5 min".
export function ageText(seconds: number): string {
  if (seconds < 60) return `${secondsFormat.format(seconds)} s`;
  const whole = Math.floor(seconds);
  if (whole < 3600) return `${Math.floor(whole / 60)} min ${whole % 60} s`;
  return `${Math.floor(whole / 3600)} h ${Math.floor((whole % 3600) / 60)} min`;
}

type SinkState = 'up' | 'behind' | 'down' | 'waiting';

function stateOf(sink: Sink): SinkState {
  if (!sink.up) return sink.error ? 'down' : 'waiting';
  return sink.spooled > 0 && sink.oldest_age_s >= BEHIND_S ? 'behind' : 'up';
}

const stateWords: Record<SinkState, string> = {
  up: 'Up',
  behind: 'Up, catching up',
  down: 'Down',
  waiting: 'No write yet',
};

function element<K extends keyof HTMLElementTagNameMap>(tag: K, className: string, text = ''): HTMLElementTagNameMap[K] {
  const made = document.createElement(tag);
  made.className = className;
  made.textContent = text;
  return made;
}

function row(sink: Sink): HTMLElement {
  const state = stateOf(sink);
  const item = element('li', 'sink');
  item.dataset.url = sink.url;
  item.dataset.state = state;
  const kind = element('span', 'sink-kind', sink.kind.toUpperCase());
  const url = element('span', 'sink-url', sink.url);
  const words = element('span', 'sink-state', stateWords[state]);
  item.append(kind, url, words);
  if (sink.spooled > 0 && state !== 'up') {
    const rows = `${countFormat.format(sink.spooled)} ${sink.spooled === 1 ? 'row' : 'rows'} waiting`;
    item.append(element('span', 'sink-behind', `${ageText(sink.oldest_age_s)} behind · ${rows}`));
  }
  if (state === 'down') item.append(element('span', 'sink-error', sink.error));
  if (sink.dropped > 0) item.append(element('span', 'sink-dropped', `${countFormat.format(sink.dropped)} dropped`));
  return item;
}

export class SinksPanel {
  private readonly list: HTMLElement;

  constructor(private readonly root: HTMLElement) {
    const title = element('h2', 'sinks-title', 'Historians');
    title.id = 'sinks-title';
    this.list = element('ul', 'sink-list');
    root.setAttribute('aria-labelledby', title.id);
    root.replaceChildren(title, this.list);
    root.hidden = true;
  }

  update(sinks: Sink[]): void {
    this.list.replaceChildren(...sinks.map(row));
    this.root.hidden = sinks.length === 0;
  }
}

// Sinks whose last write failed, for the overview's summary line.
export function sinksDown(sinks: Sink[]): number {
  return sinks.filter((sink) => stateOf(sink) === 'down').length;
}
