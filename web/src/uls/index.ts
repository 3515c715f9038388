// The ULS as the shared dashboard sees it (family_view.ts): its page, and its card's words
// for look down, which produces no distance.
import type { FamilyView } from '../family_view';
import { UlsPage } from './uls_page';

export const DOCUMENT_SECTIONS = 'ULS interface specification: §2 Interface Program, §3 measurement modes, ' +
  '§7 RS-485 network, §8 commands and formats, §9 rates and resolution, §10 errors; docs/conformance.md.';

export const uls: FamilyView = {
  name: 'uls',
  page: (sensorName) => new UlsPage(sensorName),
  documentSections: DOCUMENT_SECTIONS,
  // U113: §3 look down "A distance is not produced", so its aggregates carry no value; §8 Get
  // Unit Status "n = 3 = laser firing and Look Down Mode" says which unit that is.
  noReading: (sensor) => (sensor.status.status === 3 ? 'look down: no distance' : undefined),
};
