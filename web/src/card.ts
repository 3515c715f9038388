// One sensor's card on the overview: name, family, live value and rate, link state,
// error and lost counts, and a sparkline (uPlot) of the last minute. Gaps (no signal,
// disconnected, lost records, silence) are nulls, drawn as breaks and never joined.
import uPlot from 'uplot';
import type { Aggregate, LinkEvent, Sensor } from './api';
import { channelOf, familyTitle } from './descriptors';
import type { FamilyView } from './family_view';

export const WINDOW_S = 60;
// Longer than this between two points is a silence, drawn as a gap.
const SILENCE_S = 2;
// A card not drawn (filtered out, off screen) drops its points older than the window as they
// come, once they are this much older, so its arrays stay bounded; draw() trims to the window.
const KEEP_S = WINDOW_S + 10;

const numberFormat = new Intl.NumberFormat('en', { minimumFractionDigits: 3, maximumFractionDigits: 3 });
const rateFormat = new Intl.NumberFormat('en', { maximumFractionDigits: 1, minimumFractionDigits: 1 });

function element<K extends keyof HTMLElementTagNameMap>(tag: K, className?: string, text?: string) {
  const made = document.createElement(tag);
  if (className) made.className = className;
  if (text !== undefined) made.textContent = text;
  return made;
}

function stat(label: string): [HTMLElement, HTMLElement] {
  const box = element('div');
  const value = element('dd', undefined, '–');
  box.append(element('dt', undefined, label), value);
  return [box, value];
}

export class Card {
  readonly root: HTMLElement;
  private readonly state: HTMLElement;
  private readonly value: HTMLElement;
  private readonly unit: HTMLElement;
  private readonly rate: HTMLElement;
  private readonly errors: HTMLElement;
  private readonly lost: HTMLElement;
  private readonly lastEvent: HTMLElement;
  private readonly spark: HTMLElement;
  private plot: uPlot | null = null;
  private times: number[] = [];
  private values: (number | null)[] = [];
  private connected = false;
  private problem = false;
  private readonly familyLabel: string;  // the name in capitals: the badge and the tooltip
  private valueText = '';
  private noReading: string | undefined;  // the family's words for no value, when it has some
  // The newest aggregate not yet shown: the DOM is written once per frame (flush), not per item.
  private pending: Aggregate | null = null;

  // `view`: the family's part (families.ts), if the dashboard has one for it.
  constructor(readonly name: string, private readonly familyName: string, private readonly view?: FamilyView) {
    this.familyLabel = familyName.toUpperCase();
    const id = `card-${name}`;
    this.root = element('article', 'card');
    this.root.dataset.sensor = name;
    this.root.setAttribute('aria-labelledby', `${id}-name`);

    const head = element('header', 'card-head');
    const title = element('h2', 'name');
    title.id = `${id}-name`;
    const link = element('a', undefined, name);
    link.href = `#/sensor/${encodeURIComponent(name)}`;
    link.setAttribute('aria-describedby', `${id}-value ${id}-state`);
    title.append(link);
    const badge = element('span', 'family', this.familyLabel);
    badge.title = familyTitle(familyName) ?? this.familyLabel;
    this.state = element('span', 'state');
    this.state.id = `${id}-state`;
    head.append(title, badge, this.state);

    const reading = element('p', 'reading');
    reading.id = `${id}-value`;
    this.value = element('span', 'value', '–');
    this.unit = element('span', 'unit');
    reading.append(this.value, this.unit);

    const stats = element('dl', 'stats');
    const [rateBox, rate] = stat('Rate');
    const [errorBox, errors] = stat('Errors');
    const [lostBox, lost] = stat('Lost');
    this.rate = rate;
    this.errors = errors;
    this.lost = lost;
    stats.append(rateBox, errorBox, lostBox);

    this.spark = element('div', 'spark');
    this.spark.setAttribute('role', 'img');
    this.spark.setAttribute('aria-label', `${name}: readings of the last minute`);
    this.lastEvent = element('p', 'last-event');

    this.root.append(head, reading, stats, this.spark, this.lastEvent);
    this.setConnected(false);
    this.showValue('waiting for a reading', '', 'none');
  }

  // From GET /api/sensors (every few seconds): the counters and the link state.
  // Only what changed is written: with a hundred cards each write costs the next frame a style pass.
  update(sensor: Sensor): void {
    if (sensor.health.connected !== this.connected) this.setConnected(sensor.health.connected);
    setText(this.rate, `${rateFormat.format(sensor.health.rate_hz)} Hz`);
    setText(this.errors, String(sensor.health.errors));
    setText(this.lost, String(sensor.health.lost));
    this.errors.classList.toggle('bad', sensor.health.errors > 0);
    this.lost.classList.toggle('bad', sensor.health.lost > 0);
    this.problem = sensor.health.errors > 0 || sensor.health.lost > 0;
    // "/dev/ttyUSB2: streaming (ST)": the port is the sensor's own, so shown once, in the tooltip.
    const prefix = sensor.port ? `${sensor.port}: ` : '';
    const event = sensor.health.last_event;
    setText(this.lastEvent, prefix && event.startsWith(prefix) ? event.slice(prefix.length) : event);
    const title = sensor.port ? `${sensor.port} · ${event}` : event;
    if (this.lastEvent.title !== title) this.lastEvent.title = title;
    this.noReading = this.view?.noReading?.(sensor);
  }

  // An item of the stream: its point goes into the sparkline's arrays now, its value into the
  // DOM at the next flush().
  aggregate(data: Aggregate): void {
    const time = Date.parse(data.time) / 1000;
    this.push(time, data.last === undefined ? null : data.last);
    this.pending = data;
  }

  // Writes the newest aggregate's value (once per frame, for the cards shown).
  flush(): void {
    const data = this.pending;
    if (data === null) return;
    this.pending = null;
    if (data.last === undefined) {
      this.showValue(this.noReading ?? 'no signal', '', 'none');
    } else if (data.channel && channelOf(this.familyName, data.channel)?.quantity === 'presence') {
      // A presence reads 1 or 0: said in words, drawn as a step.
      this.showValue(data.last ? 'target present' : 'no target', '', 'live');
    } else {
      this.showValue(numberFormat.format(data.last), data.unit ?? '', 'live');
    }
    if (!this.connected) this.setConnected(true);  // a reading proves the link
    this.root.dataset.points = String(this.times.length);
  }

  get hasPending(): boolean {
    return this.pending !== null;
  }

  // Items may be missing from `time` (seconds) on: the line is not joined across.
  gap(time: number): void {
    this.push(time, null);
  }

  link(event: LinkEvent): void {
    const time = Date.parse(event.time) / 1000;
    this.lastEvent.textContent = event.message ? `${event.event}: ${event.message}` : event.event;
    this.lastEvent.title = this.lastEvent.textContent;
    if (event.event === 'disconnected') {
      this.flush();  // the last value first, then greyed as stale
      this.setConnected(false);
      this.push(time, null);
    } else if (event.event === 'connected' || event.event === 'reconnected') {
      this.setConnected(true);
    } else if (event.event === 'lost_records') {
      this.push(time, null);  // records missing here: never joined across
    }
  }

  get hasProblem(): boolean {
    return !this.connected || this.problem;
  }

  // Redraws the sparkline for the window ending at `now` (seconds).
  draw(now: number): void {
    const from = now - WINDOW_S;
    let first = 0;
    while (first < this.times.length && this.times[first] < from) first++;
    if (first > 0) {
      this.times.splice(0, first);
      this.values.splice(0, first);
    }
    if (!this.plot) this.createPlot();
    if (!this.plot) return;
    const width = Math.floor(this.spark.clientWidth);
    if (width > 0 && width !== this.plot.width) this.plot.setSize({ width, height: this.plot.height });
    this.plot.batch(() => {
      this.plot!.setData([this.times, this.values], false);
      this.plot!.setScale('x', { min: from, max: now });
    });
  }

  private createPlot(): void {
    const width = Math.floor(this.spark.clientWidth);
    if (width <= 0) return;
    const stroke = getComputedStyle(this.root).getPropertyValue('--plot').trim() || '#2563eb';
    this.plot = new uPlot(
      {
        width,
        height: 44,
        pxAlign: false,
        cursor: { show: false },
        select: { show: false, left: 0, top: 0, width: 0, height: 0 },
        legend: { show: false },
        // At least 2 % of the value (or 0.01) tall: a steady wall stays a flat line, not magnified noise.
        scales: {
          x: { time: true },
          y: {
            range: (_plot, min, max) => {
              const middle = (min + max) / 2;
              const half = Math.max((max - min) / 2, Math.abs(middle) * 0.01, 0.005) * 1.1;
              return [middle - half, middle + half];
            },
          },
        },
        axes: [{ show: false }, { show: false }],
        series: [{}, { stroke, width: 1.5, spanGaps: false, points: { show: false } }],
      },
      [[], []],
      this.spark,
    );
  }

  private push(time: number, value: number | null): void {
    const previous = this.times.length ? this.times[this.times.length - 1] : -Infinity;
    if (!(time > previous)) return;  // a replayed item after a reconnect: already drawn
    if (value !== null && this.times.length > 0 && time - previous > SILENCE_S && this.values[this.values.length - 1] !== null) {
      this.times.push(previous + 0.001);
      this.values.push(null);  // a silence is a gap, not a straight line
    }
    this.times.push(time);
    this.values.push(value);
    if (this.times[0] < time - KEEP_S) {
      let old = 0;
      while (this.times[old] < time - WINDOW_S) old++;
      this.times.splice(0, old);
      this.values.splice(0, old);
    }
  }

  private showValue(text: string, unit: string, kind: 'live' | 'none' | 'stale'): void {
    setText(this.value, text);
    setText(this.unit, unit);
    if (this.root.dataset.reading !== kind) this.root.dataset.reading = kind;
    this.valueText = unit ? `${text} ${unit}` : text;
    this.updateLabel();
  }

  private setConnected(connected: boolean): void {
    this.connected = connected;
    this.root.dataset.connected = String(connected);
    this.state.textContent = connected ? 'Connected' : 'Disconnected';
    if (!connected && this.root.dataset.reading === 'live') this.root.dataset.reading = 'stale';
    this.updateLabel();
  }

  private updateLabel(): void {
    const title = `${this.name} (${this.familyLabel}): ${this.connected ? 'connected' : 'disconnected'}, ${this.valueText}`;
    if (this.root.title !== title) this.root.title = title;
  }
}

// Setting the same text again still replaces the node and costs a style pass: skipped.
function setText(node: HTMLElement, text: string): void {
  if (node.textContent !== text) node.textContent = text;
}
