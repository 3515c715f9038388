// The ULS page, mirroring the §2 main screen: indicators, the live reading, the mode's display
// choice and §2's buttons, with the parameter panels, configuration files, capture, RS-485
// network and live plot from their own modules.
import type { Reading, Sensor } from '../api';
import { authorisedFetch, openSensorEvents, postAction } from '../api';
import { ActionBar } from '../action_bar';
import { CapturePanel } from '../capture_panel';
import { ConfigFilePanel } from '../config_file';
import { Rs485Network } from './rs485_network';
import { LivePlot } from '../live_plot';
import { UlsPanels } from './uls_panels';
import { BasicMeasurement } from './basic_measurement';

// §2 "Icons: Displayed above the black measurement window".
const INDICATORS = [
  ['connected', 'Connected', 'The service talks to the ULS (Connect, in the specification: "Activates the communication between the computer and the ULS").'],
  ['laser', 'Laser On', 'The specification: "Laser On: The laser is firing."'],
  ['gates', 'G', 'The specification: "G: Gates are set."'],
  ['cooperative', 'CT', 'The specification: "CT: Cooperative Target."'],
  ['offset', 'O', 'The specification: "O: an Offset value is being applied to measurements."'],
  ['basic', 'BM', 'The specification: "BM (Basic Measurement): The ULS is producing valid measurements more than once every two seconds."'],
] as const;
type Indicator = (typeof INDICATORS)[number][0];

// §2 "Display/Target Selection", per mode.
const DISPLAY_CHOICES: Record<string, [string, string][]> = {
  averaging: [['distance', 'Distance'], ['intensity', 'Intensity'], ['both', 'Both']],
  binning: [['first', 'First target'], ['last', 'Last target']],
};

interface UlsSample {
  time: string;
  kind?: string;
  distance_m?: number;
  pulse_width_ns?: number;  // 3 decimals: the wire's integer picoseconds (U8, U92)
  targets?: { distance_m: number; strength: number }[];
  presence?: boolean;
  error?: number;
  error_text?: string;
}

function element<K extends keyof HTMLElementTagNameMap>(tag: K, className?: string, text?: string) {
  const made = document.createElement(tag);
  if (className) made.className = className;
  if (text !== undefined) made.textContent = text;
  return made;
}

export class UlsPage {
  readonly root = element('section', 'sensor-page');
  private readonly indicators = new Map<Indicator, HTMLElement>();
  private readonly box = element('output', 'measurement');
  private readonly choices = element('fieldset', 'display');
  private readonly message = element('p', 'page-message');
  private readonly caption = element('p');
  private readonly readButton = element('button', 'action', 'Read');
  private readonly panels: UlsPanels;
  private readonly capture: CapturePanel;
  private readonly configFile: ConfigFilePanel;
  private readonly network: Rs485Network;
  private readonly plot = new LivePlot('uls');
  private readonly singleButton = element('button', 'action', 'Single Measurement');
  private mode = '';
  private display = '';
  private readonly basic = new BasicMeasurement();
  private lastSample: UlsSample | null = null;
  private source: EventSource | null = null;

  constructor(readonly name: string) {
    const back = element('a', 'back', '← All sensors');
    back.href = '#';
    const title = element('h1', 'page-title', name);
    title.tabIndex = -1;  // takes the focus when the page opens
    title.append(' ', element('span', 'family', 'ULS'));
    const row = element('ul', 'indicators');
    row.setAttribute('aria-label', 'Indicators');
    for (const [key, label, meaning] of INDICATORS) {
      const item = element('li', 'indicator', label);
      item.dataset.indicator = key;
      item.title = meaning;
      item.tabIndex = 0;  // the tooltip's text reaches keyboard and screen-reader users too
      const description = element('span', 'visually-hidden', meaning);
      description.id = `meaning-${key}`;
      item.setAttribute('aria-describedby', description.id);
      item.append(description);
      row.append(item);
      this.indicators.set(key, item);
      this.set(key, undefined);
    }
    this.box.setAttribute('aria-live', 'off');
    this.box.setAttribute('aria-label', 'Measurement');
    this.box.textContent = 'waiting for a reading';
    this.readButton.type = 'button';
    this.readButton.addEventListener('click', () => void this.read());
    const buttons = element('div', 'buttons');
    this.panels = new UlsPanels(name);
    const upload = element('button', 'action', 'Upload Settings');
    upload.type = 'button';
    upload.addEventListener('click', () => void this.panels.upload());
    buttons.append(upload, this.readButton);
    // §2 buttons, through POST /api/sensors/NAME/actions/... (docs/api.md).
    for (const [label, action, argument] of [['Pointer On', 'pointer', 'on'], ['Pointer Off', 'pointer', 'off'],
      ['Measurement Start', 'start', ''], ['Measurement Stop', 'stop', '']] as const) {
      const button = element('button', 'action', label);
      button.type = 'button';
      button.addEventListener('click', () => void this.act(action, argument, label));
      buttons.append(button);
    }
    this.singleButton.type = 'button';
    this.singleButton.hidden = true;  // §2: with Continuous Output off, "select Single Measurement"
    this.singleButton.addEventListener('click', () => void this.act('single', '', 'Single Measurement'));
    buttons.append(this.singleButton);
    const more = new ActionBar('uls', ['read', 'pointer', 'start', 'stop', 'single'],
      (action, argument, label) => this.act(action, argument, label));
    this.message.setAttribute('role', 'status');
    this.message.textContent = 'G, CT, O and the panels below show the settings once they have been read: press Read.';
    this.caption.className = 'caption';
    this.capture = new CapturePanel(name);
    // Open offers .uls files as well as TOML.
    this.configFile = new ConfigFilePanel(name, (settings) => this.panels.update(settings, true),
      '.toml,.uls,text/plain,application/toml');
    this.network = new Rs485Network(name);
    this.root.append(back, title, row, this.box, this.caption, this.choices, buttons, more.root, this.message, this.plot.root,
      this.configFile.root, this.capture.root, this.network.root,
      this.panels.message, this.panels.root);
    this.panels.load().catch((error: Error) => {
      this.panels.message.textContent = `The panels could not be built: ${error.message}`;
    });
    this.root.dataset.sensor = name;
  }

  // From GET /api/sensors: link state, US status (§8), settings as last read.
  update(sensor: Sensor, requestedAt = Infinity): void {
    this.set('connected', sensor.health.connected);
    this.network.update(sensor);
    const status = sensor.status as Record<string, unknown>;
    this.set('laser', status['laser-firing'] === undefined ? undefined : status['laser-firing'] === 'yes');
    const settings = (sensor as Sensor & { settings: Record<string, unknown> }).settings ?? {};
    const known = Object.keys(settings).length > 0;
    this.panels.update(settings, false, requestedAt);
    this.singleButton.hidden = !(known && settings.continuous === 'off');
    // U114: G when a gate is not 0 (U44: "0 = off"), CT when the cooperative filter is on, O when the offset is not 0.
    this.set('gates', known ? Number(settings['short-gate-m']) !== 0 || Number(settings['long-gate-m']) !== 0 : undefined);
    this.set('cooperative', known ? settings['cooperative-filter'] === 'on' : undefined);
    this.set('offset', known ? Number(settings['offset-m']) !== 0 : undefined);
    // §8 US: 3 look down, 7 averaging, 11 binning (U6); the setting once read.
    const mode = known ? String(settings.mode) :
      ({ 3: 'look-down', 7: 'averaging', 11: 'binning' } as Record<number, string>)[Number(status.status)] ?? this.mode;
    this.setMode(mode);  // the setting's value names are the samples' kinds
  }

  open(): void {
    this.source?.close();
    const gap = () => this.plot.gap(Date.now() / 1000);
    this.source = openSensorEvents<UlsSample>(this.name, {
      sample: (data, reading) => this.sample(data, reading),
      event: (kind) => {
        if (kind === 'disconnected') this.set('connected', false);
        if (kind === 'disconnected' || kind === 'lost_records') gap();
        if (kind === 'connected' || kind === 'reconnected') this.set('connected', true);
      },
      resumed: gap,  // nothing is drawn across skipped items
    });
    this.tick = window.setInterval(() => this.updateBasic(), 500);
    this.plot.start();
  }

  close(): void {
    this.source?.close();
    this.source = null;
    window.clearInterval(this.tick);
    this.capture.close();
    this.plot.stop();
  }

  private tick = 0;

  private sample(sample: UlsSample, reading: Reading | undefined): void {
    this.lastSample = sample;
    // A plot per mode; an error stays on the mode's plot as a gap. Binning's reading is the
    // nearest target, and the plot shows every target of the burst.
    const plot = sample.kind && sample.kind !== 'error' ? sample.kind : undefined;
    const values = reading && sample.kind === 'binning' ? sample.targets?.map((target) => target.distance_m) : undefined;
    this.plot.add({ time: sample.time, plot, reading, values });
    if (sample.kind && sample.kind !== this.mode && sample.kind !== 'error') this.setMode(sample.kind);
    const valid = sample.distance_m !== undefined || (sample.targets?.length ?? 0) > 0 || sample.presence !== undefined;
    if (valid) this.basic.valid(performance.now());
    this.show();
    this.updateBasic();
  }

  // U124 (basic_measurement.ts); the tick turns it off within 0.5 s once 2 s pass with none.
  private updateBasic(): void {
    this.set('basic', this.basic.lit(performance.now()));
  }

  private show(): void {
    const sample = this.lastSample;
    if (!sample) return;
    let text: string;
    if (sample.kind === 'look-down') {
      text = sample.presence ? 'ON' : 'OFF';  // §2: "the on/off condition of the trip signal"
    } else if (sample.kind === 'binning') {
      const targets = sample.targets ?? [];
      const target = this.display === 'last' ? targets[targets.length - 1] : targets[0];
      text = target ? `${target.distance_m.toFixed(3)} m (${this.display === 'last' ? 'last' : 'first'} of ${targets.length})` : 'no target';
    } else if (sample.distance_m !== undefined) {
      const distance = `${sample.distance_m.toFixed(3)} m`;
      const intensity = sample.pulse_width_ns !== undefined ? `${sample.pulse_width_ns.toFixed(3)} ns` : '–';
      text = this.display === 'intensity' ? intensity : this.display === 'both' ? `${distance} · ${intensity}` : distance;
    } else {
      text = sample.error_text ? `error ${sample.error}: ${sample.error_text}` : 'no signal';
    }
    this.box.textContent = text;
  }

  private setMode(mode: string): void {
    if (!mode || mode === this.mode) return;
    this.mode = mode;
    this.root.dataset.mode = mode;
    this.choices.replaceChildren();
    const legend = element('legend', undefined, 'Display');
    this.choices.append(legend);
    this.caption.textContent = mode === 'averaging'
      ? 'Intensity: the received pulse width, in ns.'
      : mode === 'binning' ? 'A target of the last measurement, and how many it found.' : '';
    const choices = DISPLAY_CHOICES[mode];
    if (!choices) {
      this.display = '';
      this.choices.append(element('p', 'hint', 'Look down: the ON/OFF condition of the trip signal.'));
      return;
    }
    this.display = choices[0][0];
    for (const [value, label] of choices) {
      const id = `display-${value}`;
      const input = element('input');
      input.type = 'radio';
      input.name = 'display';
      input.id = id;
      input.value = value;
      input.checked = value === this.display;
      input.addEventListener('change', () => {
        this.display = value;
        this.show();
      });
      const text = element('label', undefined, label);
      text.htmlFor = id;
      this.choices.append(input, text);
    }
  }

  private async read(): Promise<void> {
    this.readButton.disabled = true;
    this.message.textContent = 'Reading the settings…';
    try {
      const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/actions/read`, { method: 'POST' });
      const body = await response.json();
      this.message.textContent = response.ok ? 'Settings read.' : `Read refused: ${body.error?.message ?? response.status}`;
      if (response.ok) {
        const settings = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/settings`);
        if (settings.ok) this.panels.update((await settings.json()) as Record<string, unknown>, true);
      }
    } catch (error) {
      this.message.textContent = `Read failed: ${(error as Error).message}`;
    } finally {
      this.readButton.disabled = false;
    }
  }

  private async act(action: string, argument: string, label: string): Promise<void> {
    this.message.textContent = `${label}…`;
    try {
      const done = await postAction(this.name, action, argument);
      this.message.textContent = done.ok ? `${label}: done${done.text ? ` (${done.text})` : ''}.`
        : `${label} refused: ${done.text}`;
    } catch (error) {
      this.message.textContent = `${label} failed: ${(error as Error).message}`;
    }
  }

  private set(key: Indicator, on: boolean | undefined): void {
    const item = this.indicators.get(key);
    if (!item) return;
    item.dataset.state = on === undefined ? 'unknown' : on ? 'on' : 'off';
  }
}
