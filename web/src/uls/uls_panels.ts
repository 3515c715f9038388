// The ULS page's parameter panels (§2 "Basic Setup" ... "Current Loop"), built from the
// settings schema (§8's command table, as the CLI) and checked before sending. Upload sends
// only the changed fields, as one PATCH; a refusal shows the §10 number and its text.
import { authorisedFetch } from '../api';
import { buildField, element, numberProblem, patchSettings } from '../settings_fields';

export interface SchemaRow {
  key: string;
  mnemonic: string;
  title: string;
  unit: string;
  writable: boolean;
  min?: number;
  max?: number;
  min_fields: number;
  max_fields: number;
  error: number;
  reference: string;
  values?: { value: number; name: string; label?: string }[];
}

// §2's parameter windows and the settings each shows (names as `rangekit uls get` prints them).
const PANELS: [string, [string, string][]][] = [
  ['Basic Setup', [['units', 'Units'], ['short-gate-m', 'Short Gate'], ['long-gate-m', 'Long Gate'], ['offset-m', 'Offset']]],
  ['Measurement Mode', [['mode', 'Mode']]],
  ['PRF and Pulses/Measure', [['prf-hz', 'PRF (averaging, binning, look down)'], ['ppm', 'Pulses/Measure (averaging, binning)']]],
  ['Averaging Parameters', [['dither', 'Dithering'], ['averaging-weight', 'Required Dither / Minimum Good Pulses']]],
  ['Laser Power', [['power', 'Laser Power']]],
  ['Output Setup', [['output-port', 'Output Port'], ['display', 'Display Mode'], ['continuous', 'Continuous Output'],
    ['autostart', 'ULS Autostart'], ['pointer-autostart', 'Pointer Autostart'], ['cooperative-filter', 'Cooperative Target'],
    ['termination', 'Termination']]],
  ['Binning Parameters', [['bin-threshold', 'Bin Hits'], ['bin-size', 'Bin Size (Range), cm (m)']]],
  ['Look Down', [['trip-point-m', 'Trip Point'], ['trip-timeout-s', 'Re-reference time'], ['time-between-events', 'Time Between Events']]],
  ['Current Loop', [['current-loop', 'Current Loop'], ['range-4ma-m', 'Range at 4 mA'], ['range-20ma-m', 'Range at 20 mA'],
    ['fault-timeout-s', 'Fault Timeout'], ['fault-current-ma', 'Fault Current']]],
];

// §3 "If the short timeout period is selected in the ULS interface, the unit will re-reference in
// 8,000 laser pulses" (U21: $TT,1F40); the field shows seconds, §8 "seconds * 3000".
const SHORT_TIMEOUT_PULSES = 8000;
const PULSES_PER_SECOND = 3000;
// §3 "a target distance that does not change for prolonged time (1,080,000 laser pulses ...)":
// what unchecking restores when the unit was read with the short timeout and nothing else was typed.
const DEFAULT_TIMEOUT_S = '360';

// §2 windows' items with no §8 command behind them: shown as what they are, never as an input.
const NO_COMMAND_NOTES: Record<string, { id: string; title: string; text: string }> = {
  'Averaging Parameters': {
    id: 'note-min-pulse-width',
    title: 'Minimum Pulse Width (not settable from a host)',
    text: 'The specification: "This value is used to reject returned receive pulses less then the value specified, in nano-seconds", ' +
      'so weak returns can be rejected. The serial protocol has no command to set or read it, so neither this page nor the CLI can; ' +
      "the emulator keeps it as a unit setting on its control socket (docs/conformance.md U41).",
  },
  'Current Loop': {
    id: 'note-current-loop-calibration',
    title: 'Calibration (not possible from a host)',
    text: 'The specification\'s "Calibrating the Current Loop": with the unit stopped and the current loop on, adjust the coarse and fine ' +
      'DAC values of the 4 mA and 20 mA set points, press Set 4 mA or Set 20 mA to output them while a precision meter ' +
      "measures the current, then SAVE them to the unit's non-volatile memory. The serial protocol has no command for the DAC values, " +
      "the set buttons or SAVE, so only LTI's Interface Program can calibrate (docs/conformance.md U108).",
  },
};

// "off (polled)" -> "off", "1 inch" -> "1-inch": how the API names a value (named_settings.cpp).
function keyName(name: string): string {
  return name.split('(')[0].trim().toLowerCase().replace(/[ _]+/g, '-').replace(/-+$/, '');
}

// Seconds as the API prints them (4 decimals, trailing zeros dropped): 8000 pulses -> "2.6667".
function secondsText(seconds: number): string {
  return String(Number(seconds.toFixed(4)));
}

function isShortTimeout(secondsField: string): boolean {
  const seconds = Number(secondsField.trim());
  return secondsField.trim() !== '' && Math.round(seconds * PULSES_PER_SECOND) === SHORT_TIMEOUT_PULSES;
}

function rangeText(row: SchemaRow): string {
  if (row.values) return '';
  const unit = row.unit ? ` ${row.unit}` : '';
  const count = row.max_fields > 1 ? (row.min_fields === row.max_fields ? `${row.max_fields} values, each ` : `${row.min_fields} or ${row.max_fields} values, each `) : '';
  return `${count}${row.min} – ${row.max}${unit}`;
}

interface Field {
  row: SchemaRow;
  input: HTMLInputElement | HTMLSelectElement;
  problem: HTMLElement;
  sent: string;  // the value as last read, in the field's own form
}

export class UlsPanels {
  private forcedAt = -Infinity;
  readonly root = element('div', 'panels');
  readonly message = element('p', 'panel-message');
  private readonly fields = new Map<string, Field>();
  private schemaLoaded = false;
  private errorDisplay = new Map<number, string>();  // §10 "ULS Interface Display" by number
  private shortTimeout?: HTMLInputElement;
  private typedTimeout = '';  // the re-reference time before Short Timeout was checked

  constructor(private readonly name: string) {
    this.message.setAttribute('role', 'status');
  }

  async load(): Promise<void> {
    const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/settings/schema`);
    if (!response.ok) throw new Error(`settings schema: ${response.status}`);
    const schema = (await response.json()) as { settings: SchemaRow[]; errors?: { number: number; display: string }[] };
    for (const error of schema.errors ?? []) this.errorDisplay.set(error.number, error.display);
    const rows = new Map(schema.settings.map((row) => [row.key, row]));
    for (const [title, entries] of PANELS) {
      const panel = element('fieldset', 'panel');
      // Output Setup's choices are long ("RS232 configuration port"): the whole row, so no select is cut short.
      if (title === 'Output Setup') panel.classList.add('wide');
      panel.append(element('legend', undefined, title));
      for (const [key, label] of entries) {
        const row = rows.get(key);
        if (row?.writable) panel.append(this.field(row, label));
        if (key === 'trip-timeout-s' && row?.writable) panel.append(this.shortTimeoutBox());
      }
      const note = NO_COMMAND_NOTES[title];
      if (note) {
        const box = element('div', 'no-command');
        box.id = note.id;
        box.append(element('p', 'no-command-title', note.title), element('p', 'no-command-text', note.text));
        panel.append(box);
      }
      this.root.append(panel);
    }
    this.schemaLoaded = true;
  }

  private field(row: SchemaRow, label: string): HTMLElement {
    const { wrapper, input, problem } = buildField({
      id: `setting-${row.key}`,
      label,
      key: row.key,
      range: rangeText(row),
      title: `${row.title} (${row.mnemonic})`,
      choices: row.values?.map((value) => ({ value: String(value.value), label: value.label ?? value.name })),
    });
    input.addEventListener('input', () => this.check(this.fields.get(row.key)!));
    input.addEventListener('change', () => this.check(this.fields.get(row.key)!));
    this.fields.set(row.key, { row, input, problem, sent: '' });
    return wrapper;
  }

  // §2 Look Down "Short Timeout": checked, the re-reference time becomes 8000 pulses (shown in
  // the field, sent by Upload Settings); unchecked, the time typed before comes back.
  private shortTimeoutBox(): HTMLElement {
    const wrapper = element('div', 'field checkbox');
    const box = element('input');
    box.type = 'checkbox';
    box.id = 'setting-short-timeout';
    box.dataset.setting = 'short-timeout';
    box.disabled = true;  // until the settings have been read
    const label = element('label', undefined, 'Short Timeout');
    label.htmlFor = box.id;
    const hint = element('span', 'range',
      `${SHORT_TIMEOUT_PULSES} pulses (about 3 s at 3000 PRF), for setting up: a presence longer than that is lost`);
    hint.id = `${box.id}-range`;
    box.setAttribute('aria-describedby', hint.id);
    box.title = 'Short Timeout (sent as TT 1F40): the unit re-references in 8,000 laser pulses';
    box.addEventListener('change', () => {
      const field = this.fields.get('trip-timeout-s');
      if (!field) return;
      if (box.checked) {
        this.typedTimeout = field.input.value;
        field.input.value = secondsText(SHORT_TIMEOUT_PULSES / PULSES_PER_SECOND);
      } else {
        const typed = this.typedTimeout;
        field.input.value = typed && !isShortTimeout(typed) ? typed : DEFAULT_TIMEOUT_S;
      }
      (field.input as HTMLInputElement).readOnly = box.checked;
      this.check(field);
    });
    wrapper.append(label, box, hint);
    this.shortTimeout = box;
    return wrapper;
  }

  // The settings as last read (GET /api/sensors): every field shows them, except one being edited.
  // `requestedAt`: when the snapshot was asked for (performance.now()). One asked before the
  // last forced update (a read, an upload, a set's answer) is older than what is shown: skipped.
  update(settings: Record<string, unknown>, force = false, requestedAt = Infinity): void {
    if (!this.schemaLoaded || Object.keys(settings).length === 0) return;
    if (force) this.forcedAt = performance.now();
    else if (requestedAt < this.forcedAt) return;
    for (const field of this.fields.values()) {
      const raw = settings[field.row.key];
      if (raw === undefined) continue;
      const value = this.formOf(field.row, raw);
      const edited = field.input.value !== field.sent && field.sent !== '';
      if (force || !edited) field.input.value = value;
      field.sent = value;
      field.input.disabled = false;
      if (force || !edited) this.check(field);
    }
    const timeout = this.fields.get('trip-timeout-s');
    if (this.shortTimeout && timeout && settings['trip-timeout-s'] !== undefined) {
      this.shortTimeout.disabled = false;
      this.shortTimeout.checked = isShortTimeout(timeout.input.value);
      (timeout.input as HTMLInputElement).readOnly = this.shortTimeout.checked;
    }
  }

  private formOf(row: SchemaRow, raw: unknown): string {
    if (!row.values) return String(raw);
    const text = String(raw);
    const byNumber = row.values.find((value) => String(value.value) === text);
    if (byNumber) return String(byNumber.value);
    const named = row.values.find((value) => keyName(value.name) === text);
    if (named) return String(named.value);
    if (text === 'on' || text === 'off') return text === 'on' ? '1' : '0';  // flags named otherwise ("idle on power up")
    return text;
  }

  // §8's range of the field (the document's numbers, served by the API); '' when it is fine.
  private problemOf(field: Field): string {
    const row = field.row;
    if (row.values) return '';
    const parts = field.input.value.split(',').map((part) => part.trim());
    if (parts.length < row.min_fields || parts.length > row.max_fields) {
      return `${row.min_fields === row.max_fields ? row.min_fields : `${row.min_fields} or ${row.max_fields}`} value${row.max_fields > 1 ? 's' : ''} separated by commas`;
    }
    for (const part of parts) {
      const whole = row.unit === 'Hz' || row.unit === 'pulses' || row.unit === 'hits';
      const problem = numberProblem(part, { min: row.min, max: row.max, unit: row.unit, whole });
      if (problem) return problem.includes('out of range') ? `${problem} (the ULS answers error ${row.error})` : problem;
    }
    return '';
  }

  private check(field: Field): boolean {
    const problem = this.problemOf(field);
    field.problem.textContent = problem;
    field.input.setAttribute('aria-invalid', problem ? 'true' : 'false');
    field.input.closest('.field')?.classList.toggle('changed', field.input.value !== field.sent);
    return problem === '';
  }

  // PATCH of the changed fields, after every field passed its check; nothing is sent otherwise.
  async upload(): Promise<void> {
    const body: Record<string, unknown> = {};
    const wrong: string[] = [];
    for (const [key, field] of this.fields) {
      if (!this.check(field)) wrong.push(key);
      if (field.input.value === field.sent || field.input.disabled) continue;
      // A named value goes by its name ("4-inches"): a bare number of a bin size is refused (§8 BS).
      const named = field.row.values?.find((value) => String(value.value) === field.input.value);
      if (named) {
        body[key] = keyName(named.name);
        continue;
      }
      const parts = field.input.value.split(',').map((part) => Number(part.trim()));
      body[key] = field.row.max_fields > 1 ? parts : parts[0];
    }
    const refusals = wrong.map((key) => {
      const field = this.fields.get(key)!;
      return { label: key, problem: field.problem.textContent ?? '', input: field.input };
    });
    const sent = await patchSettings(this.name, body, refusals, this.message);
    if (!sent) return;
    const { response, answer } = sent;
    if (!response.ok) {
      // device_error: "$AW: device error 49: Pulse Per Output Must Be Greater Than Average Weight" (§10)
      const message = answer.error?.message ?? String(response.status);
      const number = /device error (\d+)/.exec(message)?.[1];
      const display = number ? this.errorDisplay.get(Number(number)) : undefined;
      // As the Interface Program shows it (§10), then the service's whole message.
      this.message.textContent = display ? `Upload refused: ULS error ${number}: ${display} (${message})`
        : `Upload refused: ${message}`;
      this.message.dataset.state = 'error';
      return;
    }
    this.update(answer, true);
    this.message.textContent = `Uploaded and read back: ${Object.keys(body).join(', ')}.`;
    this.message.dataset.state = 'done';
  }
}
