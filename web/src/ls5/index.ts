// The LS5 as the shared dashboard sees it (family_view.ts): its page.
import type { FamilyView } from '../family_view';
import { Ls5Page } from './ls5_page';

export const DOCUMENT_SECTIONS = 'LS5 manual: §5 ordering code, §8 protocol and formulas, table 9.1 commands, ' +
  'table 9.2 parameters, §10 Ethernet; docs/conformance.md.';

export const ls5: FamilyView = {
  name: 'ls5',
  page: (sensorName) => new Ls5Page(sensorName),
  documentSections: DOCUMENT_SECTIONS,
};
