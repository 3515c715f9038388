// The LS5 page: decoded ID, live result, outputs computed by §8's formulas (ls5_outputs.ts),
// latching (FX/FR), table 9.2's parameters (ls5_panels.ts) and the live plot. An LS5 heard
// over UDP only (§10) gets the stream and a word on why it has no settings.
import type { Reading, Sensor } from '../api';
import { authorisedFetch, openSensorEvents, postAction } from '../api';
import { ActionBar } from '../action_bar';
import { LivePlot } from '../live_plot';
import { Ls5Panels } from './ls5_panels';
import {
  analogOutput, ANALOG_RANGES, decodeDiscreteOutputs, derivativeMm, discreteOutput, distanceMm, latchLimits,
  LATCHING_EFFECT, MAX_CODE, NO_SIGNAL,
} from './ls5_outputs';
import { element } from '../settings_fields';
import './ls5_page.css';

interface Ls5Sample {
  time: string;
  kind?: string;
  code?: number;
  distance_mm?: number;
  derivative_mm?: number;
  signal?: string;
}

const ANALOG_TYPE_KEY = 'rangekit-ls5-analog-';

function definition(list: HTMLElement, term: string, key: string): HTMLElement {
  const row = element('div');
  const value = element('dd', undefined, '–');
  value.dataset.id = key;
  row.append(element('dt', undefined, term), value);
  list.append(row);
  return value;
}

export class Ls5Page {
  readonly root = element('section', 'sensor-page ls5-page');
  private readonly connection = element('span', 'state');
  private readonly idList = element('dl', 'ls5-id');
  private readonly idValues = new Map<string, HTMLElement>();
  private readonly box = element('output', 'measurement');
  private readonly codeLine = element('p', 'caption');
  private readonly message = element('p', 'page-message');
  private readonly panels: Ls5Panels;
  private readonly plot = new LivePlot('ls5');
  private newest: Ls5Sample | null = null;
  private renderPending = false;
  private readonly outputs = element('section', 'ls5-outputs');
  private readonly analogValue = element('output', 'analog-value');
  private readonly analogMeter = element('meter');
  private readonly analogSelect = element('select');
  private readonly analogNote = element('p', 'hint');
  private readonly discrete: HTMLElement[] = [element('output', 'discrete'), element('output', 'discrete')];
  private readonly latchMode = element('p');
  private readonly latchPreview = element('p', 'hint');
  private readonly latchResult = element('output', 'latched');
  private readonly buttons = element('div', 'buttons');
  private readonly streamNote = element('p', 'hint stream-note');
  private identityShown = false;
  private lastResultCode: number | undefined;
  private code: number | undefined;
  private source: EventSource | null = null;
  private udpOnly = false;

  constructor(readonly name: string) {
    const back = element('a', 'back', '← All sensors');
    back.href = '#';
    const title = element('h1', 'page-title', name);
    title.tabIndex = -1;  // takes the focus when the page opens
    title.append(' ', element('span', 'family', 'LS5'), ' ', this.connection);
    this.connection.textContent = 'connecting…';
    this.idList.setAttribute('aria-label', 'Identification (ID)');
    for (const [term, key] of [['Version', 'version'], ['Lower boundary', 'lower-boundary-mm'], ['Range', 'range-mm'],
      ['Serial number', 'serial'], ['Ethernet', 'ethernet']] as const) {
      this.idValues.set(key, definition(this.idList, term, key));
    }
    this.box.setAttribute('aria-label', 'Measurement');
    this.box.textContent = 'waiting for a reading';
    this.message.setAttribute('role', 'status');
    this.panels = new Ls5Panels(name);
    this.panels.onSettings = () => this.showOutputs();
    this.buildButtons();
    this.buildOutputs();
    const stream = element('h2', 'section-title', 'Stream');
    this.streamNote.textContent = 'Results in mm; derivatives (result type 01) on an axis of their own.';
    const more = new ActionBar('ls5', ['read', 'save', 'start', 'stop', 'single', 'latch'],
      (action, argument, label) => this.act(action, argument, label));
    this.root.append(back, title, this.idList, this.box, this.codeLine, this.buttons, more.root, this.message, this.outputs,
      stream, this.streamNote, this.plot.root, element('h2', 'section-title', 'Parameters'), this.panels.message,
      this.panels.root);
    this.root.dataset.sensor = name;
  }

  private button(label: string, run: () => unknown, title: string): HTMLButtonElement {
    const button = element('button', 'action', label);
    button.type = 'button';
    button.title = title;
    button.addEventListener('click', () => void run());
    this.buttons.append(button);
    return button;
  }

  private buildButtons(): void {
    this.button('Read', () => this.read(), 'Read every parameter (R)');
    this.button('Upload Settings', () => this.panels.upload(), 'Write the changed parameters (W) and read them back');
    this.button('Save to flash', () => this.act('save', '', 'Save to flash (FL)'), 'FL: keep the parameters after power off');
    this.button('Start stream', () => this.act('start', '', 'Start stream (ST)'), 'ST: start the stream of results');
    this.button('Stop stream', () => this.act('stop', '', 'Stop stream (SB)'), 'SB: stop the stream');
    this.button('Read last result', () => this.act('single', '', 'Read last result (LR)'), 'LR: read the last result');
  }

  private buildOutputs(): void {
    this.outputs.setAttribute('aria-label', 'Outputs and latching');
    const analog = element('fieldset', 'panel');
    analog.append(element('legend', undefined, 'Analog output'));
    const typeLabel = element('label', undefined, 'Output type (from the ordering code)');
    typeLabel.htmlFor = 'ls5-analog-type';
    this.analogSelect.id = 'ls5-analog-type';
    for (const [value, range] of Object.entries(ANALOG_RANGES)) {
      const option = element('option', undefined, range.label);
      option.value = value;
      this.analogSelect.append(option);
    }
    this.analogSelect.value = localStorage.getItem(ANALOG_TYPE_KEY + this.name) ?? '4-20mA';
    this.analogSelect.addEventListener('change', () => {
      localStorage.setItem(ANALOG_TYPE_KEY + this.name, this.analogSelect.value);
      this.showOutputs();
    });
    const typeRow = element('div', 'field');
    typeRow.append(typeLabel, this.analogSelect);
    this.analogValue.id = 'ls5-analog-value';
    this.analogValue.setAttribute('aria-label', 'Analog output now');
    this.analogMeter.id = 'ls5-analog-meter';
    this.analogMeter.setAttribute('aria-label', 'Analog output between its minimum and maximum');
    const now = element('div', 'output-now');
    now.append(this.analogValue, this.analogMeter);
    analog.append(typeRow, now, this.analogNote);

    const discrete = element('fieldset', 'panel');
    discrete.append(element('legend', undefined, 'Discrete outputs'));
    const list = element('dl', 'discrete-list');
    this.discrete.forEach((output, index) => {
      output.id = `ls5-oc${index + 1}`;
      output.setAttribute('aria-label', `Discrete output ${index + 1}`);
      const row = element('div');
      row.append(element('dt', undefined, `OC${index + 1}`), element('dd'));
      row.lastElementChild!.append(output);
      list.append(row);
    });
    discrete.append(list);

    const latch = element('fieldset', 'panel');
    latch.append(element('legend', undefined, 'Latching'));
    this.latchMode.id = 'ls5-latch-mode';
    this.latchResult.id = 'ls5-latched';
    this.latchResult.setAttribute('aria-label', 'Latched result');
    this.latchResult.textContent = '–';
    const latchButtons = element('div', 'buttons');
    for (const [label, argument, title] of [['Latch (FX)', '', 'FX, then FR to show what was latched'],
      ['Read latched (FR)', 'read', 'FR: the result latched last']] as const) {
      const button = element('button', 'action', label);
      button.type = 'button';
      button.title = title;
      button.addEventListener('click', () => void this.latch(argument, label));
      latchButtons.append(button);
    }
    const resultRow = element('p');
    resultRow.append('Latched: ', this.latchResult);
    latch.append(this.latchMode, this.latchPreview, latchButtons, resultRow);
    this.outputs.className = 'panels ls5-outputs';
    this.outputs.append(analog, discrete, latch);
  }

  // From GET /api/sensors: the ID (decoded by the service from the 35 characters), link state.
  update(sensor: Sensor, requestedAt = Infinity): void {
    this.connection.textContent = sensor.health.connected ? 'connected' : 'disconnected';
    this.connection.dataset.connected = String(sensor.health.connected);
    const identity = sensor.identity as Record<string, unknown>;
    if (!this.identityShown && Object.keys(identity).length > 0) {
      this.identityShown = true;
      this.showIdentity(sensor);
    }
    const settings = (sensor as Sensor & { settings?: Record<string, unknown> }).settings ?? {};
    if (Object.keys(settings).length > 0) this.panels.update(settings, false, requestedAt);
  }

  private showIdentity(sensor: Sensor): void {
    const identity = sensor.identity as Record<string, string | number>;
    this.udpOnly = !sensor.port && !!sensor.udp;
    if (this.udpOnly) {
      this.idList.replaceChildren();
      definition(this.idList, 'Heard over UDP at', 'udp').textContent = String(identity.udp ?? sensor.udp);
      this.buttons.hidden = true;
      this.streamNote.textContent += ' A packet brings 168 results with the time it arrived, so they are ' +
        'drawn at one instant: the plot moves in steps.';
      this.outputs.hidden = true;
      this.panels.message.textContent = 'An LS5 heard over UDP only (its manual: "The Ethernet interface is only used for ' +
        'the one-way transmission of the measurement stream"): its parameters need its serial port in the site file.';
      return;
    }
    const units: Record<string, string> = { 'lower-boundary-mm': ' mm', 'range-mm': ' mm' };
    for (const [key, value] of this.idValues) {
      if (identity[key] !== undefined) value.textContent = `${identity[key]}${units[key] ?? ''}`;
    }
    this.panels.load({ version: String(identity.version ?? ''), rangeMm: Number(identity['range-mm']) || undefined,
      ethernet: String(identity.ethernet ?? '') }).then(() => {
      if (Object.keys(this.panels.settings).length === 0) this.message.textContent = 'Press Read to show the parameters.';
    }).catch((error: Error) => {
      this.panels.message.textContent = `The parameters could not be shown: ${error.message}`;
    });
    if (identity.ethernet === 'yes') {
      this.streamNote.textContent += ' An Ethernet model: it also sends its results as UDP packets of 168 results while ' +
        '"UDP data auto-stream" is on; a site file lists that stream as a sensor with `udp`.';
    }
  }

  open(): void {
    this.source?.close();
    const gap = () => this.plot.gap(Date.now() / 1000);
    this.source = openSensorEvents<Ls5Sample>(this.name, {
      sample: (data, reading) => this.sample(data, reading),
      event: (kind) => {
        if (kind === 'disconnected' || kind === 'lost_records') gap();
      },
      resumed: gap,  // nothing is drawn across skipped items
    });
    this.plot.start();
  }

  close(): void {
    this.source?.close();
    this.source = null;
    this.plot.stop();
  }

  private sample(sample: Ls5Sample, reading: Reading | undefined): void {
    // Results and derivatives on one plot: the derivatives' channel (a distance change) gets a
    // right axis of its own once one comes (L80); no-signal records (no reading) are gaps.
    this.plot.add({ time: sample.time, plot: 'ls5', reading });
    // The box, the code and the outputs show the newest sample once per animation frame: at
    // 1 kHz, writing them for every sample would cost the page its frame rate.
    if (!this.udpOnly && sample.code !== undefined && sample.code <= MAX_CODE) this.lastResultCode = sample.code;
    this.newest = sample;
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      if (this.newest) this.show(this.newest);
    });
  }

  private show(sample: Ls5Sample): void {
    const distance = sample.distance_mm;
    if (this.udpOnly) {
      this.box.textContent = distance !== undefined ? `${distance} mm` : sample.signal === 'lost' ? 'no signal' : '–';
      return;
    }
    const code = sample.code;
    if (code === undefined) return;
    this.code = code;
    const range = Number(this.idValues.get('range-mm')?.textContent?.replace(' mm', ''));
    let text: string;
    if (code === NO_SIGNAL) text = 'no signal';
    else if (code > MAX_CODE) text = 'no measurement yet';
    else if (sample.kind === 'derivative' || this.panels.settings['result-type'] === 'derivative') {
      text = `${sample.derivative_mm ?? derivativeMm(code, range).toFixed(4)} mm (derivative)`;
    } else text = `${distance ?? distanceMm(code, range).toFixed(4)} mm`;  // the service keeps the discreteness (L63)
    this.box.textContent = text;
    this.codeLine.textContent = `Code K = ${code} (0…50000 over the range${code > MAX_CODE ? '; 65534 nothing yet, 65535 no signal' : ''})`;
    this.codeLine.dataset.code = String(code);
    this.showOutputs();
  }

  // Formulas 8.3 and 8.4 from the parameters as last read and the live code.
  private showOutputs(): void {
    const settings = this.panels.settings;
    const range = ANALOG_RANGES[this.analogSelect.value];
    this.analogMeter.min = range.min;
    this.analogMeter.max = range.max;
    const code = this.code;
    const known = Object.keys(settings).length > 0;
    if (!known || code === undefined) {
      this.analogValue.textContent = known ? 'waiting for a result' : 'press Read: the output needs the limits';
      for (const output of this.discrete) output.textContent = '–';
      this.showLatching();
      return;
    }
    const lower = Number(settings['analog-lower']);
    const upper = Number(settings['analog-upper']);
    const value = analogOutput(range, lower, upper, code, this.lastResultCode);
    const enabled = settings['analog-output'] !== 'disabled';
    this.analogValue.textContent = `${value.toFixed(3)} ${range.unit}`;
    this.analogValue.dataset.value = String(value);
    this.analogValue.dataset.code = String(code);
    this.analogMeter.value = value;
    this.analogNote.textContent = enabled
      ? `Limits K_n = ${lower}, K_v = ${upper}${upper < lower ? ' (inverted)' : ''}; K = ${code}.`
      : 'Disabled (03 = 00): the output holds its value of the last measurement before it was disabled; ' +
        `with the output enabled it would be ${value.toFixed(3)} ${range.unit}.`;
    const byte = this.discreteByte(String(settings['discrete-outputs']));
    const setting = byte ? decodeDiscreteOutputs(byte) : null;
    this.discrete.forEach((output, index) => {
      if (!setting) {
        output.textContent = '–';
        return;
      }
      const first = Number(settings[`output${index + 1}-first-swing`]);
      const second = Number(settings[`output${index + 1}-second-swing`]);
      const state = discreteOutput(setting[index], first, second, code);
      output.dataset.state = setting[index].enabled ? String(state) : 'disabled';
      output.textContent = setting[index].enabled
        ? `${state} (initial value N = ${setting[index].initial}; swings ${first} – ${second})`
        : '0 (disabled)';
    });
    this.showLatching();
  }

  // Parameter 15's byte for the name the service reads ("low-high" -> "12"), from the schema.
  private discreteByte(name: string): string | null {
    const row = this.panels.rows().get('discrete-outputs');
    return row?.values?.find((value) => value.value === name)?.byte ?? null;
  }

  private showLatching(): void {
    const settings = this.panels.settings;
    const mode = settings.latching === undefined ? undefined
      : this.panels.rows().get('latching')?.values?.find((value) => value.value === settings.latching);
    if (!mode) {
      this.latchMode.textContent = 'Latching mode: press Read.';
      this.latchPreview.textContent = '';
      return;
    }
    this.latchMode.textContent = `Latching ${mode.byte}: ${LATCHING_EFFECT[mode.byte] ?? mode.label}`;
    const code = this.lastResultCode;
    const analogModes = ['02', '03'];
    const discreteModes = ['04', '05', '06', '07', '08', '09'];
    const fixed = analogModes.includes(mode.byte) ? Number(settings['analog-fixed-range'])
      : discreteModes.includes(mode.byte) ? Number(settings['discrete-fixed-range']) : undefined;
    if (fixed === undefined || code === undefined) {
      this.latchPreview.textContent = '';
      return;
    }
    const limits = latchLimits(code, fixed);
    this.latchPreview.textContent = `Latched now (K = ${code}, D = ${fixed}): G_min = ${limits.lower}, ` +
      `G_max = ${limits.upper}.`;
  }

  private async read(): Promise<void> {
    this.message.textContent = 'Reading the parameters…';
    try {
      const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/actions/read`, { method: 'POST' });
      const body = await response.json();
      if (!response.ok) {
        this.message.textContent = `Read refused: ${body.error?.message ?? response.status}`;
        return;
      }
      const settings = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/settings`);
      if (settings.ok) this.panels.update((await settings.json()) as Record<string, unknown>, true);
      this.message.textContent = 'Parameters read.';
      // The fields show the sensor's values again: a refusal of edits now gone no longer applies.
      this.panels.message.textContent = '';
      this.panels.message.dataset.state = '';
    } catch (error) {
      this.message.textContent = `Read failed: ${(error as Error).message}`;
    }
  }

  private async latch(argument: string, label: string): Promise<void> {
    const result = await this.act('latch', argument, label);
    if (result !== null) this.latchResult.textContent = result;
    // Modes 02-09 recalculate limits in the sensor: read them back so the fields and outputs show them.
    if (argument === '' && result !== null && !['00', '01'].includes(this.latchModeByte())) await this.read();
  }

  private latchModeByte(): string {
    const settings = this.panels.settings;
    return this.panels.rows().get('latching')?.values?.find((value) => value.value === settings.latching)?.byte ?? '01';
  }

  private async act(action: string, argument: string, label: string): Promise<string | null> {
    this.message.textContent = `${label}…`;
    try {
      const done = await postAction(this.name, action, argument);
      if (!done.ok) {
        this.message.textContent = `${label} refused: ${done.text}`;
        return null;
      }
      this.message.textContent = `${label}: done${done.text ? ` (${done.text})` : ''}.`;
      return done.text;
    } catch (error) {
      this.message.textContent = `${label} failed: ${(error as Error).message}`;
      return null;
    }
  }
}
