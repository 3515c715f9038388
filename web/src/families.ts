// Each family's page and card words (web/src/<family>/index.ts), listed in registered_families.ts,
// which the build generates from the registration list (families.cmake): no shared file names one.
import type { FamilyView } from './family_view';
import { registeredViews } from './registered_families';

export function familyView(name: string | undefined): FamilyView | undefined {
  return registeredViews.find((view) => view.name === name);
}
