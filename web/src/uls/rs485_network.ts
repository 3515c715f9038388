// §7 RS-485 Network on the ULS page: which units answer on the bus (as `rangekit uls bus
// scan`), and §7's Assign window with the addresses in use marked. The service refuses an
// address a unit answers at (U105); the site file keeps the old address (U106).
import type { Sensor } from '../api';
import { authorisedFetch, listSensors } from '../api';

interface ScannedUnit {
  address: string;
  code: number;
  version: string;
  duplicate: boolean;
  problem: string;
  sensor: string | null;
}

interface Scan {
  port: string;
  asked: number;
  units: ScannedUnit[];
  site: { address: string; code: number; sensor: string }[];
}

function element<K extends keyof HTMLElementTagNameMap>(tag: K, className?: string, text?: string) {
  const made = document.createElement(tag);
  if (className) made.className = className;
  if (text !== undefined) made.textContent = text;
  return made;
}

// §8 Set/Get Unit Address: "aa = unit address (Ascii single character = a-z, A-Z, or 0-9)".
const ADDRESSES = [...'abcdefghijklmnopqrstuvwxyz', ...'ABCDEFGHIJKLMNOPQRSTUVWXYZ', ...'0123456789'];

export class Rs485Network {
  readonly root = element('fieldset', 'panel rs485');
  private readonly scanButton = element('button', 'action', 'Scan the Bus');
  private readonly status = element('p', 'rs485-status');
  private readonly table = element('table', 'rs485-units');
  private readonly current = element('output', 'rs485-current');
  private readonly select = element('select');
  private readonly assignButton = element('button', 'action', 'Assign');
  private readonly warning = element('p', 'hint');
  private site = new Map<string, string>();  // address -> the site file's sensor on this port
  private answering = new Map<string, ScannedUnit>();  // address -> the unit the last scan heard
  private address = '';
  private built = false;

  constructor(private readonly name: string) {
    this.root.append(element('legend', undefined, 'RS-485 Network'));
    this.status.setAttribute('role', 'status');
  }

  private siteAddress = '';  // the sensor's address in the site file

  // From GET /api/sensors: the sensor's address (a bus unit) or none (alone on its port).
  update(sensor: Sensor): void {
    if (this.built) return;
    this.built = true;
    const address = sensor.address;
    if (address === undefined || address === null) {
      this.root.append(element('p', 'hint', `${this.name} is alone on its port (the $ protocol; no address in the ` +
        'site file): the RS-485 network is for units addressed on a bus.'));
      return;
    }
    this.address = address;
    this.siteAddress = this.address;
    // The site file's other units on this port, marked from the start (§7's asterisks).
    listSensors().then((sensors) => {
      for (const other of sensors) {
        if (other.port === sensor.port && other.address !== undefined) this.site.set(other.address, other.name);
      }
      this.fillSelect();
    }).catch(() => undefined);
    this.scanButton.type = 'button';
    this.scanButton.addEventListener('click', () => void this.scan());
    this.table.hidden = true;
    const caption = element('caption', undefined, 'Units that answered');
    const head = element('tr');
    for (const title of ['Address', 'Unit (ID)', 'Site sensor', 'Note']) head.append(element('th', undefined, title));
    this.table.append(caption, head);

    // §7 "Assign RS-485 Address": "Current address:", "Select Address:", Assign.
    const assign = element('div', 'rs485-assign');
    const currentLabel = element('span', undefined, 'Current address: ');
    this.current.id = `rs485-current-${this.name}`;
    this.current.textContent = this.address;
    const selectLabel = element('label', undefined, 'Select Address');
    this.select.id = `rs485-select-${this.name}`;
    selectLabel.htmlFor = this.select.id;
    this.select.setAttribute('aria-describedby', `rs485-key-${this.name}`);
    this.select.addEventListener('change', () => this.explain());
    this.assignButton.type = 'button';
    this.assignButton.addEventListener('click', () => void this.assign());
    assign.append(currentLabel, this.current, selectLabel, this.select, this.assignButton);
    const key = element('p', 'hint', '* already assigned in the network: a unit of the site file on this port, or one ' +
      'that answered the last scan. The service refuses an address a unit answers at; one of the site file may be ' +
      'used when that unit is being replaced.');
    key.id = `rs485-key-${this.name}`;
    this.warning.setAttribute('role', 'status');
    this.root.append(this.scanButton, this.status, this.table, assign, key, this.warning);
    this.fillSelect();
    this.status.textContent = `Unit ${this.address} on ${this.name}'s bus. Scan asks every address a unit can have (a-z, A-Z, 0-9).`;
  }

  // §7: "Values with an asterisk have already been assigned in the network".
  private fillSelect(): void {
    const chosen = this.select.value;
    this.select.replaceChildren();
    for (const address of ADDRESSES) {
      const sensor = this.site.get(address);
      const heard = this.answering.get(address);
      const used = sensor !== undefined || heard !== undefined;
      const who = sensor ?? (heard ? 'answers' : '');
      const option = element('option', undefined, used ? `${address} * (${who})` : address);
      option.value = address;
      option.dataset.inUse = used ? 'true' : 'false';
      this.select.append(option);
    }
    const free = ADDRESSES.find((address) => !this.site.has(address) && !this.answering.has(address));
    this.select.value = chosen && ADDRESSES.includes(chosen) ? chosen : free ?? ADDRESSES[0];
    this.explain();
  }

  private explain(): void {
    const address = this.select.value;
    const sensor = this.site.get(address);
    const heard = this.answering.get(address);
    this.warning.dataset.state = '';
    this.warning.textContent = address === this.address ? `${address} is this unit's address now.`
      : heard ? `${address} is in use: a unit answers there${sensor ? ` (${sensor})` : ''}; Assign will be refused.`
        : sensor ? `${address} is ${sensor}'s address in the site file, and did not answer the last scan: use it only ` +
          'if that unit is being replaced.' : '';
  }

  private async scan(): Promise<void> {
    this.scanButton.disabled = true;
    this.status.textContent = `Scanning: asking the ${ADDRESSES.length} possible addresses a few at a time ` +
      'between the polls (about 15 s)…';
    try {
      const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/bus/scan`, { method: 'POST' });
      const body = (await response.json()) as Scan & { error?: { message: string } };
      if (!response.ok) {
        this.status.textContent = `Scan refused: ${body.error?.message ?? response.status}`;
        return;
      }
      this.answering = new Map(body.units.map((unit) => [unit.address, unit]));
      this.site = new Map(body.site.map((entry) => [entry.address, entry.sensor]));
      this.table.querySelectorAll('tr.unit').forEach((row) => row.remove());
      for (const unit of body.units) {
        const row = element('tr', 'unit');
        row.dataset.address = unit.address;
        const note = unit.duplicate ? `two or more units hold this address: ${unit.problem}` : unit.problem;
        for (const text of [unit.address, unit.version, unit.sensor ?? 'not in the site file', note]) {
          row.append(element('td', undefined, text));
        }
        this.table.append(row);
      }
      this.table.hidden = false;
      const missing = body.site.filter((entry) => !this.answering.has(entry.address)).map((entry) => `${entry.address} (${entry.sensor})`);
      this.status.textContent = `${body.units.length} unit${body.units.length === 1 ? '' : 's'} answered of ` +
        `${body.asked} addresses asked on ${body.port}` +
        (missing.length ? `; silent: ${missing.join(', ')}.` : '.');
      this.fillSelect();
    } catch (error) {
      this.status.textContent = `Scan failed: ${(error as Error).message}`;
    } finally {
      this.scanButton.disabled = false;
    }
  }

  private async assign(): Promise<void> {
    const to = this.select.value;
    this.assignButton.disabled = true;
    this.warning.textContent = `Assigning ${to} to the unit at ${this.address}…`;
    try {
      const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/bus/assign`, {
        method: 'POST',
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify({ from: this.address, to }),
      });
      const body = await response.json();
      if (!response.ok) {
        this.warning.textContent = `Assign refused: ${body.error?.message ?? response.status}`;
        this.warning.dataset.state = 'error';
        return;
      }
      this.warning.dataset.state = 'done';
      const from = this.address;
      if (to === from) {
        this.warning.textContent = `The unit keeps address ${to}.`;
        return;
      }
      this.address = to;
      this.current.textContent = to === this.siteAddress ? to : `${to} (the site file says ${this.siteAddress})`;
      this.answering.delete(from);
      this.answering.set(to, { address: to, code: to.charCodeAt(0), version: '', duplicate: false, problem: '', sensor: null });
      this.fillSelect();
      // U106: the site file is not rewritten; §7: the program "must be closed and reopened".
      this.warning.textContent = to === this.siteAddress ? `The unit at ${from} answers at ${to} again, as the site file says.`
        : `The unit at ${from} now answers at ${to}. The site file still names ${this.name} at address ` +
          `${this.siteAddress}, so ${this.name} shows no answer until address = "${to}" is written there and the ` +
          `service restarted, or the unit is assigned back to ${this.siteAddress}.`;
    } catch (error) {
      this.warning.textContent = `Assign failed: ${(error as Error).message}`;
    } finally {
      this.assignButton.disabled = false;
    }
  }
}
