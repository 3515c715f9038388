// The families as GET /api/families describes them, read once: titles for the badges and the
// channels' quantities and units for the cards and plots, so no shared file names a family.
import { listFamilies } from './api';
import type { Action, Channel, Family } from './api';

let known = new Map<string, Family>();
let loading: Promise<void> | null = null;

// Resolves once the descriptors are read; a refusal (no token yet) is thrown and asked again next time.
export function loadFamilies(): Promise<void> {
  loading ??= listFamilies().then(
    (families) => { known = new Map(families.map((family) => [family.name, family])); },
    (error: unknown) => { loading = null; throw error; },
  );
  return loading;
}

export function familyTitle(family: string): string | undefined {
  return known.get(family)?.title;
}

export function channelOf(family: string, key: string): Channel | undefined {
  return known.get(family)?.channels.find((channel) => channel.key === key);
}

export function actionsOf(family: string): Action[] {
  return known.get(family)?.actions ?? [];
}
