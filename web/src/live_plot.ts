// The live plot of a ULS page (issue 14 point 5), uPlot: a time window of 10 s to 1 h, Pause,
// and zoom (drag across the plot; it pauses, Resume follows the live end again). Averaging is a
// line of distances; binning every target of a measurement as a scatter; look down an ON/OFF
// step trace. No signal, an error, a disconnection or a silence over 2 s leaves a gap: nothing
// is drawn across it.
import uPlot from 'uplot';

const WINDOWS: [number, string][] = [[10, '10 s'], [60, '1 min'], [600, '10 min'], [3600, '1 h']];
const KEEP_S = 3600;
const SILENCE_S = 2;
const MAX_TARGETS = 15;  // §3: "The maximum number of targets allowed in Binning Mode is 15"

export interface PlotSample {
  time: string;
  kind?: string;
  distance_m?: number;
  targets?: { distance_m: number }[];
  presence?: boolean;
}

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
  private times: number[] = [];
  private values: (number | null)[][] = [];  // one row per series
  private paused = false;
  private windowS = 60;
  private timer = 0;

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

  start(): void {
    this.timer = window.setInterval(() => this.draw(false), 250);
  }

  stop(): void {
    window.clearInterval(this.timer);
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
    if (kind !== this.mode) this.build(kind);
    const time = Date.parse(sample.time) / 1000;
    if (!Number.isFinite(time)) return;
    const last = this.times[this.times.length - 1];
    if (last !== undefined && time - last > SILENCE_S) this.push((last + time) / 2, this.values.map(() => null));
    if (kind === 'binning') {
      const row = this.values.map((_, index) => sample.targets?.[index]?.distance_m ?? null);
      this.push(time, row);
    } else if (kind === 'look_down') {
      this.push(time, [sample.presence === undefined ? null : sample.presence ? 1 : 0]);
    } else {
      this.push(time, [sample.distance_m ?? null]);
    }
  }

  private push(time: number, row: (number | null)[]): void {
    if (this.times.length && time < this.times[this.times.length - 1]) return;  // keep x ascending
    this.times.push(time);
    row.forEach((value, index) => this.values[index].push(value));
    const oldest = time - KEEP_S;
    let drop = 0;
    while (drop < this.times.length && this.times[drop] < oldest) ++drop;
    if (drop > 0) {
      this.times.splice(0, drop);
      for (const series of this.values) series.splice(0, drop);
    }
    this.root.dataset.points = String(this.times.length);
  }

  private setPaused(paused: boolean): void {
    this.paused = paused;
    this.root.dataset.paused = String(paused);
    this.pauseButton.textContent = paused ? 'Resume' : 'Pause';
    if (!paused) this.draw(true);
  }

  private build(kind: string): void {
    this.plot?.destroy();
    this.mode = kind;
    this.root.dataset.mode = kind;
    this.times = [];
    const stroke = '#1d4ed8';
    let series: uPlot.Series[];
    let yScale: uPlot.Scale = {};
    if (kind === 'binning') {
      series = Array.from({ length: MAX_TARGETS }, (_, index) => ({
        label: `target ${index + 1}`, stroke, paths: () => null, points: { show: true, size: 4, fill: stroke },
      }));
    } else if (kind === 'look_down') {
      series = [{ label: 'ON/OFF', stroke, width: 2, spanGaps: false, paths: uPlot.paths.stepped!({ align: 1 }) }];
      yScale = { range: [-0.2, 1.2] };
    } else {
      series = [{ label: 'distance (m)', stroke, width: 1.5, spanGaps: false, points: { show: false } }];
    }
    this.values = series.map(() => []);
    const width = Math.max(300, this.area.clientWidth || 760);
    this.plot = new uPlot({
      width,
      height: 240,
      scales: { x: { time: true }, y: yScale },
      legend: { show: kind !== 'binning' },
      axes: [{}, kind === 'look_down'
        ? { values: (_plot, ticks) => ticks.map((tick) => (tick === 1 ? 'ON' : tick === 0 ? 'OFF' : '')), splits: () => [0, 1] }
        : { label: 'm' }],
      series: [{}, ...series],
      hooks: {
        // A drag across the plot zooms (uPlot's own select): the live end stops moving under it.
        setSelect: [(plot) => { if (plot.select.width > 0) this.setPaused(true); }],
      },
    }, [[], ...series.map(() => [])], this.area);
  }

  private draw(force: boolean): void {
    if (!this.plot || (this.paused && !force)) return;
    this.plot.setData([this.times, ...this.values] as uPlot.AlignedData, false);
    const end = this.times.length ? this.times[this.times.length - 1] : Date.now() / 1000;
    this.plot.setScale('x', { min: end - this.windowS, max: end });
    this.root.dataset.drawnEnd = String(end);
  }
}
