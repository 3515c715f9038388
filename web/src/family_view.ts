// What a family's folder (web/src/FAMILY/) gives the shared dashboard: its sensor page and what
// its overview card says beyond the channels' descriptors. families.ts lists them.
import type { Sensor } from './api';

export interface SensorPage {
  readonly name: string;
  readonly root: HTMLElement;
  open(): void;
  close(): void;
  update(sensor: Sensor, requestedAt?: number): void;
}

export interface FamilyView {
  name: string;  // as GET /api/families names it
  page(sensorName: string): SensorPage;
  // The card's words for a moment without a value, when the sensor's state says more than "no signal".
  noReading?(sensor: Sensor): string | undefined;
}
