// An LS5's live plot (issue 14 point 5) on its sensor page: every sample of the sensor's own
// stream (`/api/sensors/NAME/events`, unmerged, so a 1 kHz LS5 sends 1000 a second), results
// in mm and, with «Type of preliminary result» 01, derivatives on their own axis (L80).
// Link events leave gaps. The LS5 page (table 9.2, outputs, latching) builds around this.
import { LivePlot } from './live_plot';
import type { PlotSample } from './live_plot';

export class Ls5LiveView {
  readonly plot = new LivePlot();
  private source: EventSource | null = null;

  constructor(readonly name: string) {}

  get root(): HTMLElement {
    return this.plot.root;
  }

  open(): void {
    this.source?.close();
    const query = new URLSearchParams();
    const token = sessionStorage.getItem('rangekit-token');
    if (token) query.set('token', token);
    this.source = new EventSource(`/api/sensors/${encodeURIComponent(this.name)}/events?${query.toString()}`);
    this.source.addEventListener('sample', (message) => {
      const item = JSON.parse((message as MessageEvent<string>).data) as { data: PlotSample };
      this.plot.add(item.data);
    });
    this.source.addEventListener('event', (message) => {
      const item = JSON.parse((message as MessageEvent<string>).data) as { data: { event: string; time?: string } };
      const event = item.data.event;
      if (event === 'disconnected' || event === 'lost_records') {
        const time = item.data.time ? Date.parse(item.data.time) / 1000 : Date.now() / 1000;
        this.plot.gap(Number.isFinite(time) ? time : Date.now() / 1000);
      }
    });
    this.plot.start();
  }

  close(): void {
    this.source?.close();
    this.source = null;
    this.plot.stop();
  }
}
