// The live plot of a sensor page (uPlot): a window of 10 s to 1 h, Pause and zoom; each mode
// drawn as docs/dashboard.md shows, an LS5's derivative on an axis of its own (L80: it is no
// distance). No signal, an error, a disconnection or a silence over 2 s leaves a gap.
import uPlot from 'uplot';

const WINDOWS: [number, string][] = [[10, '10 s'], [60, '1 min'], [600, '10 min'], [3600, '1 h']];
const KEEP_S = 3600;
// What is older than the hour kept goes in batches of this much: an item at a time would move
// the whole array (3.6 million rows at 1 kHz) for every sample.
const TRIM_S = 60;
const DRAW_MS = 250;
const SILENCE_S = 2;
const X_SPACE = 64;  // px at least between two time labels
const MAX_TARGETS = 15;  // §3: "The maximum number of targets allowed in Binning Mode is 15"

export interface PlotSample {
  time: string;
  kind?: string;
  distance_m?: number;
  targets?: { distance_m: number }[];
  presence?: boolean;
  distance_mm?: number;  // LS5 result, formula 8.1
  derivative_mm?: number;  // LS5 derivative, formula 8.2 (signed)
}

// The plot a sample's kind is drawn on: an LS5's results and derivatives share one plot with two axes.
function plotMode(kind: string): string {
  return kind === 'result' || kind === 'derivative' ? 'ls5' : kind;
}

const DISTANCE_MM = 'distance (mm)';
const DERIVATIVE_MM = 'derivative (mm)';

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
  private withDerivative = false;  // an LS5 plot shows its derivative axis once a derivative came
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

  constructor() {
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

  // Samples only land in the arrays (a 1 kHz LS5 sends 1000 a second); the plot is redrawn
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
    const kind = sample.kind && sample.kind !== 'error' ? sample.kind : this.mode;
    if (!kind) return;
    const mode = plotMode(kind);
    if (mode !== this.mode) this.build(mode);
    if (kind === 'derivative' && !this.withDerivative) this.showDerivative();
    const time = Date.parse(sample.time) / 1000;
    if (!Number.isFinite(time)) return;
    const last = this.times[this.times.length - 1];
    if (last !== undefined && time - last > SILENCE_S) this.push((last + time) / 2, this.values.map(() => null));
    if (kind === 'binning') {
      const row = this.values.map((_, index) => sample.targets?.[index]?.distance_m ?? null);
      this.push(time, row);
    } else if (kind === 'look_down') {
      this.push(time, [sample.presence === undefined ? null : sample.presence ? 1 : 0]);
    } else if (mode === 'ls5') {
      // One of the two is a gap in every row: the distance line ends where the derivative begins.
      this.push(time, kind === 'derivative' ? [null, sample.derivative_mm ?? null] : [sample.distance_mm ?? null, null]);
    } else {
      this.push(time, [sample.distance_m ?? null]);
    }
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
    this.withDerivative = false;
    this.root.dataset.mode = mode;
    this.times = [];
    this.values = (mode === 'binning' ? Array.from({ length: MAX_TARGETS }) : mode === 'ls5' ? [0, 1] : [0])
      .map(() => []);
    this.valueCounts = this.values.map(() => 0);
    this.gapRows = 0;
    this.lastGapTime = NaN;
    this.lastValueTime = NaN;
    this.create();
  }

  // The LS5 plot again, now with the derivative's own axis; the data drawn so far stays.
  private showDerivative(): void {
    this.withDerivative = true;
    this.create();
  }

  private create(): void {
    this.plot?.destroy();
    const mode = this.mode;
    const stroke = '#1d4ed8';
    const derivativeStroke = '#b45309';
    let series: uPlot.Series[];
    let axes: uPlot.Axis[];
    const scales: uPlot.Scales = { x: { time: true } };
    if (mode === 'binning') {
      series = Array.from({ length: MAX_TARGETS }, (_, index) => ({
        label: `target ${index + 1}`, stroke, paths: () => null, points: { show: true, size: 4, fill: stroke },
      }));
      axes = [{}, { label: 'm' }];
    } else if (mode === 'look_down') {
      series = [{ label: 'ON/OFF', stroke, width: 2, spanGaps: false, paths: uPlot.paths.stepped!({ align: 1 }) }];
      scales.y = { range: [-0.2, 1.2] };
      axes = [{}, { values: (_plot, ticks) => ticks.map((tick) => (tick === 1 ? 'ON' : tick === 0 ? 'OFF' : '')), splits: () => [0, 1] }];
    } else if (mode === 'ls5') {
      series = [{ label: DISTANCE_MM, scale: 'mm', stroke, width: 1.5, spanGaps: false, points: { show: false } }];
      axes = [{}, { scale: 'mm', label: DISTANCE_MM, stroke }];
      if (this.withDerivative) {
        series.push({ label: DERIVATIVE_MM, scale: 'derivative', stroke: derivativeStroke, width: 1.5, spanGaps: false,
          points: { show: false } });
        axes.push({ scale: 'derivative', side: 1, label: DERIVATIVE_MM, stroke: derivativeStroke, grid: { show: false },
          size: 64 });  // room for signed ticks such as -0.025 beside the label
      }
    } else {
      series = [{ label: 'distance (m)', stroke, width: 1.5, spanGaps: false, points: { show: false } }];
      axes = [{}, { label: 'm' }];
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
      legend: { show: mode !== 'binning' },
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

  // What uPlot draws: the LS5's derivative row only once its axis is there.
  private data(): uPlot.AlignedData {
    const shown = this.mode === 'ls5' && !this.withDerivative ? this.values.slice(0, 1) : this.values;
    return [this.times, ...shown] as uPlot.AlignedData;
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
