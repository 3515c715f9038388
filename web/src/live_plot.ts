// The live plot of a sensor page (uPlot): a window of 10 s to 1 h, Pause and zoom. It draws the
// readings the service sends, a series per channel: a quantity of its own gets an axis of its
// own, a presence an ON/OFF step, several values at once points. Gaps are never joined.
import uPlot from 'uplot';
import type { Reading } from './api';
import { channelOf } from './descriptors';

const WINDOWS: [number, string][] = [[10, '10 s'], [60, '1 min'], [600, '10 min'], [3600, '1 h']];
const KEEP_S = 3600;
// What is older than the hour kept goes in batches of this much: an item at a time would move
// the whole array (3.6 million rows at 1 kHz) for every sample.
const TRIM_S = 60;
const DRAW_MS = 250;
const SILENCE_S = 2;
const X_SPACE = 64;  // px at least between two time labels

// What a sensor page gives the plot for one sample: the server's reading (absent: a gap), and
// when the reading's channel holds several numbers at once (a burst's targets), all of them.
export interface PlotSample {
  time: string;
  plot?: string;  // which plot it is drawn on; a change starts a new one; none: the current plot
  reading?: Reading;
  values?: number[];
}

// One series: a channel's value, or the n-th of its values; its quantity and unit from the
// channel's descriptor (GET /api/families).
interface Column {
  channel: string;
  index: number;
  quantity: string;
  unit: string;
  several: boolean;
}

// "distance_mm" in mm reads "distance (mm)": the key without its unit, then the unit.
function channelLabel(column: Column): string {
  const name = column.channel.replace(new RegExp(`_${column.unit}$`), '').replace(/_/g, ' ');
  return column.unit ? `${name} (${column.unit})` : name;
}

const STROKES = ['#1d4ed8', '#b45309', '#047857', '#7c3aed'];

function element<K extends keyof HTMLElementTagNameMap>(tag: K, className?: string, text?: string) {
  const made = document.createElement(tag);
  if (className) made.className = className;
  if (text !== undefined) made.textContent = text;
  return made;
}

export class LivePlot {
  readonly root = element('section', 'live-plot');
  private readonly area = element('div', 'plot-area');
  private readonly pauseButton = element('button', 'action', 'Pause');
  private readonly windowSelect = element('select');
  private plot: uPlot | null = null;
  private mode = '';
  private columns: Column[] = [];  // the series, in the order their channels first came
  private times: number[] = [];
  private values: (number | null)[][] = [];  // one row per series
  private valueCounts: number[] = [];  // values (not gaps) per series, for the page's tests
  private gapRows = 0;  // rows without any value: no signal, a disconnection, lost records, a silence
  private lastGapTime = NaN;  // the newest row of gaps and the newest row with a value, for the page's tests
  private lastValueTime = NaN;
  private paused = false;
  private windowS = 60;
  private timer = 0;
  private frame = 0;
  private pushed = 0;  // rows ever pushed: a redraw is due when it moved
  private drawnPushed = -1;

  // `family`: whose channels the readings name (GET /api/families).
  constructor(private readonly family: string) {
    this.root.setAttribute('aria-label', 'Live plot');
    const controls = element('div', 'plot-controls');
    const label = element('label', undefined, 'Time window');
    label.htmlFor = 'plot-window';
    this.windowSelect.id = 'plot-window';
    for (const [seconds, text] of WINDOWS) {
      const option = element('option', undefined, text);
      option.value = String(seconds);
      option.selected = seconds === this.windowS;
      this.windowSelect.append(option);
    }
    this.windowSelect.addEventListener('change', () => {
      this.windowS = Number(this.windowSelect.value);
      this.draw(true);
    });
    this.pauseButton.type = 'button';
    this.pauseButton.addEventListener('click', () => this.setPaused(!this.paused));
    const hint = element('span', 'hint', 'Drag across the plot to zoom (it pauses); Resume follows the live end.');
    controls.append(label, this.windowSelect, this.pauseButton, hint);
    this.root.append(controls, this.area);
    this.root.dataset.paused = 'false';
  }

  // Samples only land in the arrays (a 1 kHz sensor sends 1000 a second); the plot is redrawn
  // every DRAW_MS at the start of an animation frame, and only when something came since.
  start(): void {
    this.timer = window.setInterval(() => {
      this.publishCounts();
      if (this.frame || document.hidden || this.paused || this.pushed === this.drawnPushed) return;
      this.frame = window.requestAnimationFrame(() => {
        this.frame = 0;
        this.draw(false);
      });
    }, DRAW_MS);
  }

  stop(): void {
    window.clearInterval(this.timer);
    window.cancelAnimationFrame(this.frame);
    this.frame = 0;
    this.plot?.destroy();
    this.plot = null;
  }

  // A gap at `time` (a disconnection): no line is drawn across it.
  gap(time: number): void {
    if (!this.mode) return;
    this.push(time, this.values.map(() => null));
  }

  add(sample: PlotSample): void {
    const mode = sample.plot ?? this.mode;
    if (!mode) return;
    if (mode !== this.mode) this.build(mode);
    const time = Date.parse(sample.time) / 1000;
    if (!Number.isFinite(time)) return;
    const last = this.times[this.times.length - 1];
    if (last !== undefined && time - last > SILENCE_S) this.push((last + time) / 2, this.values.map(() => null));
    const reading = sample.reading;
    if (!reading) {
      this.push(time, this.values.map(() => null));
      return;
    }
    const numbers = sample.values ?? [reading.value];
    this.ensureColumns(reading, numbers.length, sample.values !== undefined);
    // Every other series is a gap in this row: one channel's line ends where another's begins.
    const row: (number | null)[] = this.values.map(() => null);
    this.columns.forEach((column, index) => {
      if (column.channel === reading.channel) row[index] = numbers[column.index] ?? null;
    });
    this.push(time, row);
  }

  // The series a reading needs: its channel's, as many as its values; the plot is made again
  // with them, the rows so far kept (gaps in the new series).
  private ensureColumns(reading: Reading, count: number, several: boolean): void {
    const have = this.columns.filter((column) => column.channel === reading.channel).length;
    if (have >= count) return;
    const channel = channelOf(this.family, reading.channel);
    for (let index = have; index < count; index++) {
      this.columns.push({ channel: reading.channel, index, quantity: channel?.quantity ?? '', unit: channel?.unit ?? reading.unit,
        several });
      this.values.push(this.times.map(() => null));
      this.valueCounts.push(0);
    }
    this.create();
  }

  private push(time: number, row: (number | null)[]): void {
    if (this.times.length && time < this.times[this.times.length - 1]) return;  // keep x ascending
    this.times.push(time);
    this.pushed++;
    let empty = true;
    row.forEach((value, index) => {
      this.values[index].push(value);
      if (value !== null) {
        this.valueCounts[index]++;
        empty = false;
      }
    });
    if (empty) {
      this.gapRows++;
      this.lastGapTime = time;
    } else {
      this.lastValueTime = time;
    }
    if (this.times[0] >= time - KEEP_S - TRIM_S) return;
    const oldest = time - KEEP_S;
    let drop = 0;
    while (drop < this.times.length && this.times[drop] < oldest) ++drop;
    this.times.splice(0, drop);
    for (const series of this.values) series.splice(0, drop);
  }

  private setPaused(paused: boolean): void {
    this.paused = paused;
    this.root.dataset.paused = String(paused);
    this.pauseButton.textContent = paused ? 'Resume' : 'Pause';
    if (!paused) this.draw(true);
  }

  private build(mode: string): void {
    this.mode = mode;
    this.root.dataset.mode = mode;
    this.columns = [];
    this.times = [];
    this.values = [];
    this.valueCounts = [];
    this.gapRows = 0;
    this.lastGapTime = NaN;
    this.lastValueTime = NaN;
    this.create();
  }

  private create(): void {
    this.plot?.destroy();
    // Descriptors read after the series began (the token came later) still set their look.
    for (const column of this.columns) {
      const channel = channelOf(this.family, column.channel);
      if (channel) Object.assign(column, { quantity: channel.quantity, unit: channel.unit });
    }
    const series: uPlot.Series[] = [];
    const axes: uPlot.Axis[] = [{}];
    const scales: uPlot.Scales = { x: { time: true } };
    const several = this.columns.some((column) => column.several);
    // A scale per quantity and unit: the first on the left, each other one on the right, each
    // in its series' colour when there are several.
    const scaleOf = (column: Column) => `${column.quantity}:${column.unit}`;
    const scaleNames = [...new Set(this.columns.map(scaleOf))];
    const strokeOf = (column: Column) => STROKES[scaleNames.indexOf(scaleOf(column)) % STROKES.length];
    scaleNames.forEach((scale, index) => {
      const column = this.columns.find((one) => scaleOf(one) === scale)!;
      axes.push(this.axis(column, scale, scaleNames.length > 1 ? strokeOf(column) : undefined, index > 0));
      if (column.quantity === 'presence') scales[scale] = { range: [-0.2, 1.2] };
    });
    for (const column of this.columns) {
      const scale = scaleOf(column);
      const stroke = strokeOf(column);
      if (column.several) {
        series.push({ label: `${column.channel} ${column.index + 1}`, scale, stroke, paths: () => null,
          points: { show: true, size: 4, fill: stroke } });
      } else if (column.quantity === 'presence') {
        series.push({ label: 'ON/OFF', scale, stroke, width: 2, spanGaps: false, paths: uPlot.paths.stepped!({ align: 1 }) });
      } else {
        series.push({ label: channelLabel(column), scale, stroke, width: 1.5, spanGaps: false, points: { show: false } });
      }
    }
    // Time labels at least X_SPACE px apart: in the 10 s window uPlot's default (50) gave
    // half seconds, ":26.500 :27.000", almost touching; whole seconds read clearly.
    axes[0] = { space: X_SPACE };
    this.root.dataset.axes = axes.slice(1).map((axis) => axis.label ?? '').join('|');
    this.root.dataset.series = series.map((one) => one.label).join('|');
    this.publishCounts();  // the counts that go with these axes
    const width = Math.max(300, this.area.clientWidth || 760);
    this.plot = new uPlot({
      width,
      height: 240,
      scales,
      legend: { show: !several },
      axes,
      series: [{}, ...series],
      hooks: {
        // A drag across the plot zooms (uPlot's own select): the live end stops moving under it.
        setSelect: [(plot) => { if (plot.select.width > 0) this.setPaused(true); }],
        // The time labels drawn, for the page's tests (uPlot draws them on the canvas only).
        draw: [(plot) => {
          const values = (plot.axes[0] as unknown as { _values?: (string | number)[] })._values;
          if (values) this.root.dataset.xLabels = values.join('|');
        }],
        // The x span shown, for the page's tests (a zoom narrows it, Resume gives the window back).
        setScale: [(plot, key) => {
          if (key !== 'x') return;
          this.root.dataset.xMin = String(plot.scales.x.min);
          this.root.dataset.xMax = String(plot.scales.x.max);
        }],
      },
    }, this.data(), this.area);
  }

  // A presence as ON and OFF; a further quantity on the right, with room for signed ticks
  // such as -0.025 beside its label.
  private axis(column: Column, scale: string, stroke: string | undefined, right: boolean): uPlot.Axis {
    if (column.quantity === 'presence') {
      return { scale, values: (_plot, ticks) => ticks.map((tick) => (tick === 1 ? 'ON' : tick === 0 ? 'OFF' : '')),
        splits: () => [0, 1] };
    }
    const axis: uPlot.Axis = { scale, label: channelLabel(column) };
    if (stroke) axis.stroke = stroke;
    return right ? { ...axis, side: 1, grid: { show: false }, size: 64 } : axis;
  }

  private data(): uPlot.AlignedData {
    return [this.times, ...this.values] as uPlot.AlignedData;
  }

  private draw(force: boolean): void {
    if (!this.plot || (this.paused && !force)) return;
    this.drawnPushed = this.pushed;
    this.plot.setData(this.data(), false);
    const end = this.times.length ? this.times[this.times.length - 1] : Date.now() / 1000;
    this.plot.setScale('x', { min: end - this.windowS, max: end });
    this.root.dataset.drawnEnd = String(end);
  }

  // For the page's tests: rows kept, values (not gaps) per series, rows that are gaps, and the
  // times (s) of the newest of each.
  private publishCounts(): void {
    this.root.dataset.points = String(this.times.length);
    this.root.dataset.values = this.valueCounts.join('|');
    this.root.dataset.gaps = String(this.gapRows);
    this.root.dataset.lastGap = String(this.lastGapTime);
    this.root.dataset.lastValue = String(this.lastValueTime);
  }
}
