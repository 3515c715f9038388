// A sensor page's configuration files: save and open the TOML of `rangekit FAMILY config
// save|load`, made and read by the service (docs/api.md), so a bad file is refused by the CLI's
// tables, with its line, key and range, before anything reaches the sensor (U104).
import { authorisedFetch } from './api';

function element<K extends keyof HTMLElementTagNameMap>(tag: K, className?: string, text?: string) {
  const made = document.createElement(tag);
  if (className) made.className = className;
  if (text !== undefined) made.textContent = text;
  return made;
}

export class ConfigFilePanel {
  readonly root = element('fieldset', 'panel config-file');
  private readonly saveButton = element('button', 'action', 'Save Configuration');
  private readonly openInput = element('input');
  private readonly status = element('p', 'config-status', 'Save writes the unit\'s settings, read now, to a TOML file; Open uploads one.');

  // `loaded`: the settings as read back after an upload, for the panels; `accept`: the file
  // types Open offers, as the family's own tools name them.
  constructor(private readonly name: string, private readonly loaded: (settings: Record<string, unknown>) => void,
    accept = '.toml,text/plain,application/toml') {
    this.root.append(element('legend', undefined, 'Configuration file'));
    this.saveButton.type = 'button';
    this.saveButton.addEventListener('click', () => void this.save());
    this.openInput.type = 'file';
    this.openInput.id = `config-open-${name}`;
    this.openInput.accept = accept;
    this.openInput.addEventListener('change', () => void this.open());
    const openLabel = element('label', 'config-open', 'Open Configuration');
    openLabel.htmlFor = this.openInput.id;
    this.status.setAttribute('role', 'status');
    const row = element('div', 'buttons');
    row.append(this.saveButton, openLabel, this.openInput);
    this.root.append(row, this.status);
  }

  private say(text: string, state: '' | 'error' | 'done'): void {
    this.status.textContent = text;
    this.status.dataset.state = state;
  }

  // The TOML `rangekit FAMILY config save` writes, read from the unit now, downloaded as NAME.toml.
  private async save(): Promise<void> {
    this.saveButton.disabled = true;
    this.say('Reading the settings for the file…', '');
    try {
      const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/config`, { method: 'POST' });
      if (!response.ok) {
        const body = await response.json().catch(() => ({}));
        this.say(`Save refused: ${body.error?.message ?? response.status}`, 'error');
        return;
      }
      const text = await response.text();
      const link = element('a');
      link.href = URL.createObjectURL(new Blob([text], { type: 'application/toml' }));
      link.download = `${this.name}.toml`;
      link.hidden = true;
      this.root.append(link);
      link.click();
      link.remove();
      window.setTimeout(() => URL.revokeObjectURL(link.href), 60_000);
      this.say(`Saved ${link.download} (${text.split('\n').filter((line) => /^[a-z0-9-]+ =/.test(line)).length} settings).`, 'done');
    } catch (error) {
      this.say(`Save failed: ${(error as Error).message}`, 'error');
    } finally {
      this.saveButton.disabled = false;
    }
  }

  // Uploads the chosen file; the service checks every value before the first byte goes to the unit.
  private async open(): Promise<void> {
    const file = this.openInput.files?.[0];
    if (!file) return;
    this.openInput.value = '';  // the same file can be opened again
    if (file.size > 64 * 1024) {
      this.say(`Nothing sent: ${file.name} is ${file.size} bytes, more than a configuration file (64 KiB at most).`, 'error');
      return;
    }
    this.say(`Checking and uploading ${file.name}…`, '');
    try {
      const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(this.name)}/config`, {
        method: 'PUT',
        headers: { 'Content-Type': 'application/toml' },
        body: await file.text(),
      });
      const body = (await response.json()) as Record<string, unknown> & { error?: { message: string } };
      if (!response.ok) {
        // "the uploaded configuration:30: 'short-gate-m' is outside ...": named after the user's file.
        const message = (body.error?.message ?? String(response.status)).replace(/^the uploaded configuration/, file.name);
        // 400: refused by the tables before anything was sent; otherwise the unit or the link failed midway.
        this.say(response.status === 400 ? `Nothing sent: ${message}` : `Upload failed: ${message}`, 'error');
        return;
      }
      this.loaded(body);
      this.say(`Opened ${file.name}: every setting uploaded, read back and verified.`, 'done');
    } catch (error) {
      this.say(`Open failed: ${(error as Error).message}`, 'error');
    }
  }
}
