// The LS5 as the shared dashboard sees it (family_view.ts): its page.
import type { FamilyView } from '../family_view';
import { Ls5Page } from './ls5_page';

export const ls5: FamilyView = {
  name: 'ls5',
  page: (sensorName) => new Ls5Page(sensorName),
};
