// The service's API as the page uses it (docs/api.md): the families' descriptors, the sensor
// list, the historian sinks and the one Server-Sent Events stream of every sensor, merged to
// max_rate points a second.

export interface Health {
  connected: boolean;
  rate_hz: number;
  records: number;
  errors: number;
  no_signal: number;
  lost: number;
  bad_frames: number;
  disconnects: number;
  reconnects: number;
  last_seen: string | null;
  last_event: string;
}

export interface Sensor {
  name: string;
  family: string;  // a name of GET /api/families
  port: string;
  address?: string;       // the unit address as its family writes it: "A", "0x9C", "26"
  address_code?: number;  // the same address as the byte on the wire
  udp?: string;
  connected: boolean;
  streaming: boolean;
  identity: Record<string, unknown>;
  status: Record<string, unknown>;
  health: Health;
}

// `event: aggregate`: the samples of 1/max_rate s; min/max/last absent when all were gaps.
export interface Aggregate {
  time: string;
  count: number;
  gaps: number;
  min?: number;
  max?: number;
  last?: number;
  unit?: string;
  channel?: string;  // what min/max/last are of: a channel key of GET /api/families
}

// `event: event`: a link event (connected, disconnected, reconnected, lost_records, ...).
export interface LinkEvent {
  time: string;
  event: string;
  message?: string;
  count?: number;
}

export interface Item<T> {
  id: number;
  sensor: string;
  type: string;
  data: T;
  reading?: Reading;  // a sample's one number, absent for a gap
}

// The number a sample's family defines for it, named by one of the family's channels.
export interface Reading {
  channel: string;
  value: number;
  unit: string;
}

// GET /api/families: what each family's descriptors say, so the page needs no list of its own.
export interface Channel {
  key: string;
  quantity: string;  // 'distance', 'distance_change', 'presence', ...
  unit: string;      // 'm', 'mm', 'ns'; '' for a count or a state
  description: string;
  form: 'number' | 'flag' | 'state' | 'targets';  // how a sample's line writes it
  decimals: number;
  in_stream: boolean;  // false: kept in captures only
  states: string[];    // a state's names, 0 first
}

// A kind of sample and the keys its line carries, in order.
export interface Kind {
  name: string;
  channels: string[];
}

// POST /api/sensors/{name}/actions/{action}: what a sensor of the family does, and the values
// its argument takes (none: no argument).
export interface Action {
  name: string;
  description: string;
  arguments: string[];
  argument_optional: boolean;
}

export interface Family {
  name: string;
  title: string;
  channels: Channel[];
  kinds: Kind[];
  actions: Action[];
}

// Beyond loopback the service wants its token on every read, stream and write (docs/security.md).
// The page takes it from its address (#token=... or ?token=) and keeps it for the tab.
export function token(): string {
  const fromHash = new URLSearchParams(location.hash.replace(/^#/, '')).get('token');
  const fromQuery = new URLSearchParams(location.search).get('token');
  const found = fromHash ?? fromQuery;
  if (found) sessionStorage.setItem('rangekit-token', found);
  return found ?? sessionStorage.getItem('rangekit-token') ?? '';
}

export function setToken(value: string): void {
  sessionStorage.setItem('rangekit-token', value);
}

// A refused read: the status tells the page whether to ask for the token.
export class ReadError extends Error {
  constructor(readonly status: number, message: string) {
    super(message);
  }
}

export async function listSensors(): Promise<Sensor[]> {
  const response = await authorisedFetch('/api/sensors');
  if (!response.ok) throw new ReadError(response.status, `GET /api/sensors: ${response.status} ${response.statusText}`);
  const body = (await response.json()) as { sensors: Sensor[] };
  return body.sensors;
}

// GET /api/sinks: a historian the service writes every reading to (docs/sinks.md).
export interface Sink {
  kind: string;   // 'influx'
  url: string;    // without its password
  up: boolean;    // the historian confirmed the last write
  error: string;  // why the last write failed; '' when none did
  written: number;
  spooled: number;  // rows waiting in the spool
  spool_bytes: number;
  dropped: number;
  rejected: number;
  failures: number;
  oldest_age_s: number;  // of the oldest row waiting; 0 when none waits
}

export async function listSinks(): Promise<Sink[]> {
  const response = await authorisedFetch('/api/sinks');
  if (!response.ok) throw new ReadError(response.status, `GET /api/sinks: ${response.status} ${response.statusText}`);
  return (await response.json()) as Sink[];
}

export async function listFamilies(): Promise<Family[]> {
  const response = await authorisedFetch('/api/families');
  if (!response.ok) throw new ReadError(response.status, `GET /api/families: ${response.status} ${response.statusText}`);
  const body = (await response.json()) as { families: Family[] };
  return body.families;
}

// One sensor's own stream, every sample unmerged (a sensor page's live plot).
function sensorEventsUrl(name: string): string {
  const query = new URLSearchParams();
  const value = token();
  if (value) query.set('token', value);
  return `/api/sensors/${encodeURIComponent(name)}/events?${query.toString()}`;
}

// What a sensor page does with its stream: each sample with its reading, each event by its
// name, and a resume that skipped items (the service restarted, or kept no more of them).
export interface SensorEventHandlers<S> {
  sample(data: S, reading: Reading | undefined): void;
  event(kind: string): void;
  resumed(): void;
}

export function openSensorEvents<S>(name: string, on: SensorEventHandlers<S>): EventSource {
  const source = new EventSource(sensorEventsUrl(name));
  source.addEventListener('sample', (message) => {
    const item = JSON.parse((message as MessageEvent<string>).data) as { data: S; reading?: Reading };
    on.sample(item.data, item.reading);
  });
  source.addEventListener('event', (message) => {
    on.event((JSON.parse((message as MessageEvent<string>).data) as { data: { event: string } }).data.event);
  });
  source.addEventListener('resume', () => on.resumed());
  return source;
}

export function eventsUrl(maxRate: number): string {
  const query = new URLSearchParams({ max_rate: String(maxRate) });
  const value = token();
  if (value) query.set('token', value);
  return `/api/events?${query.toString()}`;
}

// Why a stream does not open: an EventSource cannot see the status, so ask once with fetch.
export async function streamRefusal(url: string): Promise<number | null> {
  const abort = new AbortController();
  try {
    const response = await fetch(url, { signal: abort.signal, cache: 'no-store' });
    return response.ok ? null : response.status;
  } catch {
    return 0;  // the service cannot be reached
  } finally {
    abort.abort();
  }
}

// A link the browser follows by itself (a download): the token in its query, as for a stream.
export function withToken(url: string): string {
  const value = token();
  if (!value) return url;
  return `${url}${url.includes('?') ? '&' : '?'}token=${encodeURIComponent(value)}`;
}

// A read or a write (docs/api.md): same origin, and the token when the service wants one.
export function authorisedFetch(url: string, init: RequestInit = {}): Promise<Response> {
  const headers = new Headers(init.headers);
  const value = token();
  if (value) headers.set('Authorization', `Bearer ${value}`);
  return fetch(url, { ...init, headers, cache: 'no-store' });
}

// An action of the sensor's family, done: the service's line for a person, or why it was refused.
export async function postAction(sensor: string, action: string, argument: string):
Promise<{ ok: boolean; text: string }> {
  const query = argument ? `?argument=${encodeURIComponent(argument)}` : '';
  const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(sensor)}/actions/${action}${query}`,
    { method: 'POST' });
  const body = await response.json();
  if (!response.ok) return { ok: false, text: String(body.error?.message ?? response.status) };
  return { ok: true, text: String(body.result ?? '') };
}
