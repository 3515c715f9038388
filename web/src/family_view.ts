// What a family's folder (web/src/FAMILY/) gives the shared dashboard: its sensor page and what
// its overview card says beyond the channels' descriptors. The build lists them from families.cmake.
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
  // The page's foot: the document and the sections the page follows, the one place they are named
  // (as a command's --help footer). tests/architecture/section_numbers_test.cpp allows § only there.
  documentSections: string;
}
