// §2 File Menu on the sensor's page: Start Capture, Stop Capture and View Capture, through
// the service's captures (docs/api.md, "Captures"): the file is kept by the service, and the
// page offers it in the §2 `.log` layout of each mode (U100), as CSV, JSON lines and, once
// stopped, SQLite.
import { authorisedFetch, withToken } from './api';

interface CaptureInfo {
  id: string;
  active: boolean;
  samples: number;
  events: number;
  lost: number;
  error: string;
  download: Record<string, string>;
}

function element<K extends keyof HTMLElementTagNameMap>(tag: K, className?: string, text?: string) {
  const made = document.createElement(tag);
  if (className) made.className = className;
  if (text !== undefined) made.textContent = text;
  return made;
}

const FORMATS: [string, string][] = [['log', '.log (Interface Program layout)'], ['csv', 'CSV'], ['jsonl', 'JSON lines'], ['sqlite', 'SQLite']];

export class CapturePanel {
  readonly root = element('fieldset', 'panel capture');
  private readonly status = element('p', 'capture-status', 'No capture yet.');
  private readonly startButton = element('button', 'action', 'Start Capture');
  private readonly stopButton = element('button', 'action', 'Stop Capture');
  private readonly viewButton = element('button', 'action', 'View Capture');
  private readonly links = element('p', 'capture-links');
  private readonly view = element('pre', 'capture-view');
  private capture: CaptureInfo | null = null;
  private timer = 0;

  constructor(private readonly name: string) {
    this.root.append(element('legend', undefined, 'Capture'));
    this.status.setAttribute('role', 'status');
    for (const button of [this.startButton, this.stopButton, this.viewButton]) button.type = 'button';
    this.startButton.addEventListener('click', () => void this.start());
    this.stopButton.addEventListener('click', () => void this.stop());
    this.viewButton.addEventListener('click', () => void this.show());
    this.stopButton.disabled = true;
    this.viewButton.disabled = true;
    this.view.hidden = true;
    this.view.tabIndex = 0;  // scrollable from the keyboard
    this.view.setAttribute('aria-label', 'The capture in the Interface Program\'s .log layout');
    const buttons = element('div', 'buttons');
    buttons.append(this.startButton, this.stopButton, this.viewButton);
    // What the §2 columns hold here (U100): §2 names them but gives no units for time or intensity.
    const note = element('p', 'hint', 'The .log has the Interface Program\'s columns for the mode: time of day in UTC, distances in m, ' +
      'intensity as the unit sends it (pulse width in ps). The file stays with the service.');
    this.root.append(buttons, this.status, this.links, note, this.view);
  }

  close(): void {
    window.clearInterval(this.timer);
  }

  private async start(): Promise<void> {
    const response = await authorisedFetch('/api/captures', {
      method: 'POST',
      headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ sensors: [this.name] }),
    });
    const body = await response.json();
    if (!response.ok) {
      this.status.textContent = `Start Capture refused: ${body.error?.message ?? response.status}`;
      return;
    }
    this.show_(body as CaptureInfo);
    window.clearInterval(this.timer);
    this.timer = window.setInterval(() => void this.refresh(), 1000);
  }

  private async refresh(): Promise<void> {
    if (!this.capture) return;
    const response = await authorisedFetch(`/api/captures/${encodeURIComponent(this.capture.id)}`);
    if (response.ok) this.show_((await response.json()) as CaptureInfo);
  }

  private async stop(): Promise<void> {
    if (!this.capture) return;
    window.clearInterval(this.timer);
    const response = await authorisedFetch(`/api/captures/${encodeURIComponent(this.capture.id)}/stop`, { method: 'POST' });
    const body = await response.json();
    if (!response.ok) {
      this.status.textContent = `Stop Capture refused: ${body.error?.message ?? response.status}`;
      return;
    }
    this.show_(body as CaptureInfo);
  }

  // View Capture: the `.log` as the Interface Program writes it, on the page.
  private async show(): Promise<void> {
    if (!this.capture) return;
    const response = await authorisedFetch(this.capture.download.log);
    const text = await response.text();
    this.view.hidden = false;
    if (!response.ok) {
      this.view.textContent = `No .log: ${text}`;
      return;
    }
    const lines = text.split('\n');
    this.view.textContent = lines.length > 200 ? `${lines.slice(0, 200).join('\n')}\n… (${lines.length - 200} more lines in the file)` : text;
  }

  private show_(capture: CaptureInfo): void {
    this.capture = capture;
    this.root.dataset.capture = capture.active ? 'active' : 'stopped';
    this.status.textContent = `Capture ${capture.id}: ${capture.active ? 'capturing' : 'stopped'}, ${capture.samples} samples, ` +
      `${capture.events} events, ${capture.lost} lost${capture.error ? `; ${capture.error}` : ''}.`;
    this.startButton.disabled = capture.active;
    this.stopButton.disabled = !capture.active;
    this.viewButton.disabled = false;
    this.links.replaceChildren('Download: ');
    for (const [format, label] of FORMATS) {
      if (format === 'sqlite' && capture.active) continue;  // offered once stopped (docs/api.md)
      const link = element('a', 'download', label);
      link.href = withToken(capture.download[format]);
      link.dataset.format = format;
      link.setAttribute('download', '');
      this.links.append(link, ' ');
    }
  }
}
