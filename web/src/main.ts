// The overview: a card per sensor, live from one Server-Sent Events stream at MAX_RATE points
// a second each (the service merges samples, so a 1 kHz sensor costs 4 points a second), the
// counters from GET /api/sensors and the historians from GET /api/sinks every POLL_MS. A
// sensor's page is its family's (families.ts).
import 'uplot/dist/uPlot.min.css';
import './style.css';
import { eventsUrl, listSensors, listSinks, ReadError, setToken, streamRefusal, token } from './api';
import type { Aggregate, Item, LinkEvent, Sensor } from './api';
import { Card } from './card';
import { loadFamilies } from './descriptors';
import { familyView } from './families';
import type { SensorPage } from './family_view';
import { OverviewFrames } from './overview_frames';
import { SinksPanel, sinksDown } from './sinks_panel';

const MAX_RATE = 4;
const POLL_MS = 2000;
// After an interruption, a new stream from now (see openStream): at once when the last one had
// been live a while (the service cut it off), else after a pause, as the browser would retry.
const REOPEN_SOON_MS = 100;
const REOPEN_MS = 2000;
const LIVE_A_WHILE_MS = 2000;

const grid = document.getElementById('sensors') as HTMLElement;
const summary = document.getElementById('summary') as HTMLElement;
const notice = document.getElementById('notice') as HTMLElement;
const filter = document.getElementById('filter') as HTMLInputElement;
const problemsOnly = document.getElementById('problems') as HTMLInputElement;
const sinksPanel = new SinksPanel(document.getElementById('sinks') as HTMLElement);

const overview = document.getElementById('overview') as HTMLElement;
const sensorView = document.getElementById('sensor-view') as HTMLElement;
const controls = document.querySelector('.controls') as HTMLElement;
const cards = new Map<string, Card>();
let families = new Map<string, string>();
let sensorPage: SensorPage | null = null;
let streamState: 'connecting' | 'live' | 'interrupted' = 'connecting';
let historiansDown = 0;
// The service's clock, advanced by ours between items, so the sparklines slide smoothly.
let serverTime = Date.now() / 1000;
let serverTimeAt = performance.now();

function now(): number {
  return serverTime + (performance.now() - serverTimeAt) / 1000;
}
const frames = new OverviewFrames(now);

function heard(time: string): void {
  const seconds = Date.parse(time) / 1000;
  if (seconds > now()) {
    serverTime = seconds;
    serverTimeAt = performance.now();
  }
}

function showNotice(content: Node | string | null): void {
  notice.replaceChildren();
  if (content === null) {
    notice.hidden = true;
    return;
  }
  notice.append(content);
  notice.hidden = false;
}

function applyFilter(): void {
  const text = filter.value.trim().toLowerCase();
  for (const card of cards.values()) {
    const hidden = !(card.name.toLowerCase().includes(text) && (!problemsOnly.checked || card.hasProblem));
    if (card.root.hidden === hidden) continue;
    card.root.hidden = hidden;
    if (!hidden) card.flush();  // its value as of now; the sparkline follows once it is on screen
  }
  updateSummary();
}

function updateSummary(): void {
  let connected = 0;
  let shown = 0;
  for (const card of cards.values()) {
    if (card.root.dataset.connected === 'true') connected++;
    if (!card.root.hidden) shown++;
  }
  const disconnected = cards.size - connected;
  const parts = [`${cards.size} sensors`, `${connected} connected`];
  if (disconnected > 0) parts.push(`${disconnected} disconnected`);
  if (shown !== cards.size) parts.push(`${shown} shown`);
  if (historiansDown > 0) parts.push(`${historiansDown} ${historiansDown === 1 ? 'historian' : 'historians'} down`);
  parts.push(streamState === 'live' ? 'live' : streamState === 'connecting' ? 'connecting…' : 'live stream interrupted');
  const text = parts.join(' · ');
  if (summary.textContent !== text) summary.textContent = text;
  if (summary.dataset.stream !== streamState) summary.dataset.stream = streamState;
}

function cardFor(sensor: Pick<Sensor, 'name' | 'family'>): Card {
  let card = cards.get(sensor.name);
  if (!card) {
    card = new Card(sensor.name, sensor.family, familyView(sensor.family));
    cards.set(sensor.name, card);
    grid.append(card.root);
    frames.watch(card);
  }
  return card;
}

async function poll(): Promise<void> {
  try {
    const requestedAt = performance.now();
    const [sensors, , sinks] = await Promise.all([listSensors(), loadFamilies(), listSinks()]);
    families = new Map(sensors.map((sensor) => [sensor.name, sensor.family]));
    for (const sensor of sensors) cardFor(sensor).update(sensor);
    sinksPanel.update(sinks);
    historiansDown = sinksDown(sinks);
    const shown = sensorPage && sensors.find((sensor) => sensor.name === sensorPage!.name);
    if (shown) sensorPage!.update(shown, requestedAt);
    if (streamState !== 'interrupted') showNotice(null);
  } catch (error) {
    if (error instanceof ReadError && error.status === 401) {
      if (!document.querySelector('.token-form')) showNotice(tokenForm());
    } else {
      showNotice(`The service does not answer (${(error as Error).message}); trying again.`);
    }
  }
  applyFilter();
}

function tokenForm(): HTMLElement {
  const form = document.createElement('form');
  form.className = 'token-form';
  const text = document.createElement('p');
  text.textContent =
    'This service listens beyond loopback, so reading it needs the token it printed at its first start.';
  const label = document.createElement('label');
  label.htmlFor = 'token';
  label.textContent = 'Service token';
  const input = document.createElement('input');
  input.id = 'token';
  input.type = 'password';
  input.autocomplete = 'off';
  const button = document.createElement('button');
  button.type = 'submit';
  button.textContent = 'Use token';
  form.append(text, label, input, button);
  form.addEventListener('submit', (event) => {
    event.preventDefault();
    setToken(input.value.trim());
    showNotice(null);
    openStream();
    void poll();
  });
  return form;
}

let source: EventSource | null = null;
let reopening: number | undefined;

// On an error the page opens a new stream from now itself, rather than letting the browser
// resume with Last-Event-ID: at a site's size (100 sensors at 1 kHz) the service's replay of
// its ring overflows the stream's queue, cuts it off again, and the page never recovers. The
// items missed are a gap in every sparkline.
function openStream(): void {
  source?.close();
  window.clearTimeout(reopening);
  const url = eventsUrl(MAX_RATE);
  const opened = new EventSource(url);
  source = opened;
  streamState = 'connecting';
  let liveSince = Infinity;
  opened.addEventListener('open', () => {
    liveSince = performance.now();
    streamState = 'live';
    showNotice(null);
    updateSummary();
  });
  opened.addEventListener('aggregate', (message) => {
    const item = JSON.parse((message as MessageEvent<string>).data) as Item<Aggregate>;
    heard(item.data.time);
    const card = cards.get(item.sensor);  // a sensor not listed yet comes with the next poll
    if (!card) return;
    card.aggregate(item.data);
    frames.changed(card);
  });
  opened.addEventListener('event', (message) => {
    const item = JSON.parse((message as MessageEvent<string>).data) as Item<LinkEvent>;
    heard(item.data.time);
    cards.get(item.sensor)?.link(item.data);
    updateSummary();
  });
  opened.addEventListener('error', () => {
    opened.close();
    if (source !== opened) return;
    streamState = 'interrupted';
    updateSummary();
    const time = now();
    for (const card of cards.values()) card.gap(time);
    // A refusal the EventSource cannot see: asked once with fetch.
    void streamRefusal(url).then((status) => {
      if (source !== opened) return;
      if (status === 401) {
        showNotice(tokenForm());
        return;
      }
      if (status === 0) showNotice('The service cannot be reached; the page reconnects when it answers again.');
      const wasLive = performance.now() - liveSince > LIVE_A_WHILE_MS;
      reopening = window.setTimeout(openStream, status === null && wasLive ? REOPEN_SOON_MS : REOPEN_MS);
    });
  });
}

// "#/sensor/NAME": that sensor's page; anything else: the overview.
function route(): void {
  const match = location.hash.match(/^#\/sensor\/(.+)$/);
  const name = match ? decodeURIComponent(match[1]) : null;
  if (sensorPage && sensorPage.name !== name) {
    sensorPage.close();
    sensorPage = null;
  }
  sensorView.replaceChildren();
  if (name === null) {
    overview.hidden = false;
    controls.hidden = false;
    sensorView.hidden = true;
    document.title = 'rangekit · sensors';
    return;
  }
  overview.hidden = true;
  controls.hidden = true;
  sensorView.hidden = false;
  document.title = `rangekit · ${name}`;
  const view = familyView(families.get(name));
  if (view) {
    sensorPage ??= view.page(name);
    const foot = document.createElement('footer');
    foot.className = 'document-sections';
    foot.textContent = view.documentSections;
    sensorView.append(sensorPage.root, foot);
    sensorPage.open();
    void poll();
  } else {
    const back = document.createElement('a');
    back.href = '#';
    back.className = 'back';
    back.textContent = '← All sensors';
    const title = document.createElement('h1');
    title.className = 'page-title';
    title.textContent = name;
    title.tabIndex = -1;
    const text = document.createElement('p');
    text.textContent = 'No sensor of this site has that name.';
    sensorView.append(back, title, text);
  }
  (sensorView.querySelector('h1') as HTMLElement | null)?.focus();
}

window.addEventListener('hashchange', route);
filter.addEventListener('input', applyFilter);
problemsOnly.addEventListener('change', applyFilter);

token();  // keeps a token given in the address for this tab
void poll().then(() => {
  route();
  openStream();
  setInterval(() => void poll(), POLL_MS);
});
