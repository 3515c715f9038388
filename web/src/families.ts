// The registration list: every family the dashboard has a page for, one line each, as
// src/families/list.hpp on the service's side. The only shared file that names a family.
import type { FamilyView } from './family_view';
import { ls5 } from './ls5';
import { uls } from './uls';

const views: FamilyView[] = [uls, ls5];

export function familyView(name: string | undefined): FamilyView | undefined {
  return views.find((view) => view.name === name);
}
