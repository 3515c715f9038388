// The LS5 page's parameters: table 9.2 grouped as §8 explains them, built from the settings
// schema the CLI uses and checked before sending (settings_fields.ts). Upload sends only the
// changed fields, as one PATCH; the service checks again and reads every byte back.
import { authorisedFetch } from '../api';
import { buildField, element, numberProblem, patchSettings } from '../settings_fields';
import type { FieldView } from '../settings_fields';
import { distanceMm, MAX_CODE } from './ls5_outputs';

export interface Ls5SchemaRow {
  key: string;
  title: string;
  unit: string;
  addresses: string[];
  writable: boolean;
  link: boolean;
  ethernet_only: boolean;
  since: string | null;
  min?: number;
  max?: number;
  step?: number;
  format?: 'ipv4' | 'mac';
  values?: { value: string; name: string; label: string; byte: string; since: string | null }[];
}

// §8's sections and the table 9.2 values each explains (L73: the page's grouping).
export const GROUPS: [string, string[]][] = [
  ['Serial interface', ['network-address', 'power-on-state', 'byte-format', 'baud-rate']],
  ['Measurement and output period', ['period-ms', 'thinning']],
  ['Exposure', ['max-exposure-us', 'priority']],
  ['Signal absence', ['signal-absence-ms']],
  ['Pre-filtering', ['pre-filter', 'averaging-points', 'median-points']],
  ['Preliminary result', ['result-type']],
  ['Analog output', ['analog-output', 'analog-lower', 'analog-upper', 'analog-fixed-range']],
  ['Discrete outputs', ['discrete-outputs', 'output1-first-swing', 'output1-second-swing',
    'output2-first-swing', 'output2-second-swing', 'discrete-fixed-range']],
  ['Triggering and latching', ['triggering', 'latching']],
  ['Ethernet', ['ip-address', 'gateway', 'subnet-mask', 'destination-ip', 'mac-address', 'destination-mac',
    'destination-port', 'source-port', 'udp-auto-stream']],
];

// A named value as its select lists it: table 9.2's byte, then its meaning.
function choiceLabel(value: { byte: string; label: string }): string {
  return `${value.byte} – ${value.label}`;
}

// Choices longer than this many characters do not fit a select in a column of the panels' grid
// (about 170 px at 1400 px: "06 – 230400 baud" fits; browser.ls5_page measures every select).
const WIDE_CHOICE = 20;

// "LS5.9.0" -> [9, 0]; "LS5.12.x" -> [12, 0].
function versionParts(text: string | null | undefined): [number, number] | null {
  const match = /^LS5\.(\d+)\.(\d+|x)/.exec(text ?? '');
  return match ? [Number(match[1]), match[2] === 'x' ? 0 : Number(match[2])] : null;
}

export function hasFirmware(version: string | undefined, since: string | null): boolean {
  if (!since) return true;
  const have = versionParts(version);
  const need = versionParts(since);
  if (!have || !need) return true;  // unknown: the service refuses what the sensor lacks
  return have[0] !== need[0] ? have[0] > need[0] : have[1] >= need[1];
}

interface Field extends FieldView {
  row: Ls5SchemaRow;
  sent: string;  // the value as last read
  available: boolean;
}

export interface Ls5Identity {
  version?: string;
  rangeMm?: number;
  ethernet?: string;
}

export class Ls5Panels {
  private forcedAt = -Infinity;
  readonly root = element('div', 'panels');
  readonly message = element('p', 'panel-message');
  readonly fields = new Map<string, Field>();
  private schemaLoaded = false;
  private identity: Ls5Identity = {};
  settings: Record<string, unknown> = {};
  onSettings: (settings: Record<string, unknown>) => void = () => {};

  constructor(private readonly name: string) {
    this.message.setAttribute('role', 'status');
  }

  rows(): Map<string, Ls5SchemaRow> {
    return new Map([...this.fields].map(([key, field]) => [key, field.row]));
  }

  async load(identity: Ls5Identity): Promise<void> {
    this.identity = identity;
    const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/settings/schema`);
    if (!response.ok) throw new Error(`settings schema: ${response.status}`);
    const schema = (await response.json()) as { settings: Ls5SchemaRow[] };
    const rows = new Map(schema.settings.map((row) => [row.key, row]));
    const ethernet = identity.ethernet === 'yes';
    for (const [title, keys] of GROUPS) {
      const shown = keys.map((key) => rows.get(key)).filter((row): row is Ls5SchemaRow => !!row)
        .filter((row) => ethernet || !row.ethernet_only);
      if (shown.length === 0) continue;
      const panel = element('fieldset', 'panel');
      // Long choices ("05 – imparity control, 2 stop bits", the latching modes of 1F) would be cut
      // in a column: such a group takes the whole row, as the ULS page's Output Setup does.
      if (shown.some((row) => row.values?.some((value) => choiceLabel(value).length > WIDE_CHOICE))) {
        panel.classList.add('wide');
      }
      panel.append(element('legend', undefined, title));
      for (const row of shown) panel.append(this.field(row));
      if (shown.some((row) => row.link)) {
        panel.append(element('p', 'hint', 'Address, byte format and baud rate change how the service reaches the ' +
          'sensor: change them in the site file and with `rangekit ls5 set`.'));
      }
      this.root.append(panel);
    }
    this.schemaLoaded = true;
    if (Object.keys(this.settings).length > 0) this.update(this.settings, true);
  }

  // "0 – 50000 (0 – 40.001 mm) · address 13/14": the document's range, then where it lives.
  private rangeText(row: Ls5SchemaRow, available: boolean): string {
    const parts: string[] = [];
    if (row.min !== undefined && row.max !== undefined) {
      const unit = row.unit && row.unit !== 'code' ? ` ${row.unit}` : '';
      const mm = row.unit === 'code' && this.identity.rangeMm ? ` (0 – ${this.identity.rangeMm} mm)` : '';
      parts.push(`${row.min} – ${row.max}${unit}${row.step === 2 ? ', odd' : ''}${mm}`);
    }
    if (row.format === 'ipv4') parts.push('a.b.c.d');
    if (row.format === 'mac') parts.push('XX:XX:XX:XX:XX:XX');
    parts.push(`address ${row.addresses.join('/')}`);
    if (!available) parts.push(`needs ${row.since}; this sensor is ${this.identity.version}`);
    if (row.link) parts.push('shown only');
    return parts.join(' · ');
  }

  private field(row: Ls5SchemaRow): HTMLElement {
    const available = hasFirmware(this.identity.version, row.since);
    const view = buildField({
      id: `ls5-${row.key}`,
      label: row.unit && row.unit !== 'code' ? `${row.title}, ${row.unit}` : row.title,
      key: row.key,
      range: this.rangeText(row, available),
      title: `${row.key} (parameter ${row.addresses.join('/')})`,
      choices: row.values?.map((value) => ({
        value: value.value,
        label: choiceLabel(value),
        disabled: !hasFirmware(this.identity.version, value.since),
      })),
    });
    const field: Field = { ...view, row, sent: '', available };
    if (row.unit === 'code') {
      const mm = element('span', 'range mm');
      mm.dataset.mmFor = row.key;
      view.wrapper.insertBefore(mm, view.problem);
    }
    view.input.addEventListener('input', () => this.check(field));
    view.input.addEventListener('change', () => this.check(field));
    this.fields.set(row.key, field);
    return view.wrapper;
  }

  // The settings as last read (GET /api/sensors): every field shows them, except one being edited.
  // `requestedAt`: when the snapshot was asked for (performance.now()). One asked before the
  // last forced update (a read, an upload, a set's answer) is older than what is shown: skipped.
  update(settings: Record<string, unknown>, force = false, requestedAt = Infinity): void {
    if (Object.keys(settings).length === 0) return;
    if (force) this.forcedAt = performance.now();
    else if (requestedAt < this.forcedAt) return;
    this.settings = settings;
    this.onSettings(settings);
    if (!this.schemaLoaded) return;
    for (const field of this.fields.values()) {
      const raw = settings[field.row.key];
      if (raw === undefined) continue;
      const value = String(raw);
      const edited = field.input.value !== field.sent && field.sent !== '';
      if (force || !edited) field.input.value = value;
      field.sent = value;
      field.input.disabled = !field.row.writable || !field.available;
      if (force || !edited) this.check(field);
    }
  }

  // Table 9.2's range of the field (from the schema); '' when it is fine.
  problemOf(field: Field): string {
    const row = field.row;
    const text = field.input.value.trim();
    if (row.values) return '';
    if (row.format === 'ipv4') {
      const parts = text.split('.');
      return parts.length === 4 && parts.every((part) => /^\d{1,3}$/.test(part) && Number(part) <= 255) ? ''
        : `'${text}' is not an IPv4 address like 192.168.0.3`;
    }
    if (row.format === 'mac') {
      return /^([0-9A-Fa-f]{2}:){5}[0-9A-Fa-f]{2}$/.test(text) ? '' : `'${text}' is not a MAC address like 1E:30:6C:A2:00:9D`;
    }
    const problem = numberProblem(text, {
      min: row.min, max: row.max, unit: row.unit === 'code' ? '' : row.unit, whole: (row.step ?? 1) >= 1, step: row.step,
    });
    if (problem) return problem;
    // §8.11: "The first swing of the discrete output must be less than (or equal to) the second swing".
    const swing = /^output([12])-(first|second)-swing$/.exec(row.key);
    if (swing) {
      const other = this.fields.get(`output${swing[1]}-${swing[2] === 'first' ? 'second' : 'first'}-swing`);
      const otherValue = Number(other?.input.value);
      const first = swing[2] === 'first' ? Number(text) : otherValue;
      const second = swing[2] === 'first' ? otherValue : Number(text);
      if (Number.isFinite(first) && Number.isFinite(second) && first > second) {
        return `the first swing (${first}) must not be above the second (${second})`;
      }
    }
    return '';
  }

  check(field: Field): boolean {
    const problem = field.input.disabled ? '' : this.problemOf(field);
    field.problem.textContent = problem;
    field.input.setAttribute('aria-invalid', problem ? 'true' : 'false');
    field.wrapper.classList.toggle('changed', field.input.value !== field.sent);
    const mm = field.wrapper.querySelector<HTMLElement>('[data-mm-for]');
    if (mm) {
      const code = Number(field.input.value);
      const range = this.identity.rangeMm;
      mm.textContent = !problem && range && field.input.value.trim() !== '' && code <= MAX_CODE
        ? `= ${distanceMm(code, range).toFixed(4).replace(/\.?0+$/, '')} mm` : '';
    }
    return problem === '';
  }

  // PATCH of the changed fields, after every field passed its check; nothing is sent otherwise.
  async upload(): Promise<void> {
    const body: Record<string, string> = {};
    const wrong: string[] = [];
    for (const [key, field] of this.fields) {
      if (field.input.disabled) continue;
      if (!this.check(field)) wrong.push(key);
      if (field.input.value !== field.sent) body[key] = field.input.value.trim();
    }
    const refusals = wrong.map((key) => {
      const field = this.fields.get(key)!;
      return { label: field.row.title, problem: field.problem.textContent ?? '', input: field.input };
    });
    const sent = await patchSettings(this.name, body, refusals, this.message);
    if (!sent) return;
    const { response, answer } = sent;
    if (!response.ok) {
      this.message.textContent = `Upload refused: ${answer.error?.message ?? response.status}`;
      this.message.dataset.state = 'error';
      return;
    }
    this.update(answer, true);
    this.message.textContent = `Uploaded and read back: ${Object.keys(body).join(', ')}. ` +
      'The sensor keeps them until power off; Save to flash (FL) keeps them after.';
    this.message.dataset.state = 'done';
  }
}
