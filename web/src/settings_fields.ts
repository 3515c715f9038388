// What the settings panels of every sensor page share (each family's groups of settings):
// an element helper, one labelled field (its range, its problem, wired for screen readers),
// and the check of one number against the document's range, made before anything is sent, and
// the upload of what changed.
import { authorisedFetch } from './api';

export function element<K extends keyof HTMLElementTagNameMap>(tag: K, className?: string, text?: string) {
  const made = document.createElement(tag);
  if (className) made.className = className;
  if (text !== undefined) made.textContent = text;
  return made;
}

export interface FieldView {
  wrapper: HTMLElement;
  input: HTMLInputElement | HTMLSelectElement;
  hint: HTMLElement;
  problem: HTMLElement;
}

// A label, an input (a select when `choices` are given), the range text and a problem line.
export function buildField(options: {
  id: string;
  label: string;
  key: string;
  range: string;
  title: string;
  choices?: { value: string; label: string; disabled?: boolean }[];
}): FieldView {
  const wrapper = element('div', 'field');
  const labelElement = element('label', undefined, options.label);
  labelElement.htmlFor = options.id;
  let input: HTMLInputElement | HTMLSelectElement;
  if (options.choices) {
    const select = element('select');
    for (const choice of options.choices) {
      const option = element('option', undefined, choice.label);
      option.value = choice.value;
      option.disabled = choice.disabled ?? false;
      select.append(option);
    }
    input = select;
  } else {
    const text = element('input');
    text.type = 'text';
    text.inputMode = 'decimal';
    text.autocomplete = 'off';
    input = text;
  }
  input.id = options.id;
  input.dataset.setting = options.key;
  input.disabled = true;  // until the settings have been read
  const hint = element('span', 'range', options.range);
  hint.id = `${options.id}-range`;
  const problem = element('span', 'problem');
  problem.id = `${options.id}-problem`;
  problem.setAttribute('role', 'alert');
  input.setAttribute('aria-describedby', `${hint.id} ${problem.id}`);
  input.title = options.title;
  wrapper.append(labelElement, input, hint, problem);
  return { wrapper, input, hint, problem };
}

export interface NumberRule {
  min?: number;
  max?: number;
  unit?: string;
  whole?: boolean;  // integers only
  step?: number;    // a multiple of step above min (a period in 0.1 ms steps, an odd count of points)
}

// '' when `text` is a number the rule allows; otherwise what is wrong, naming the range.
export function numberProblem(text: string, rule: NumberRule): string {
  const part = text.trim();
  const number = Number(part);
  if (part === '' || !Number.isFinite(number)) return `'${part}' is not a number`;
  if (rule.whole && !Number.isInteger(number)) return `${part} is not a whole number`;
  const unit = rule.unit ? ` ${rule.unit}` : '';
  if (rule.min !== undefined && rule.max !== undefined && (number < rule.min || number > rule.max)) {
    return `${part} is out of range: ${rule.min} – ${rule.max}${unit}`;
  }
  if (rule.step !== undefined && rule.step > 0) {
    const steps = (number - (rule.min ?? 0)) / rule.step;
    if (Math.abs(steps - Math.round(steps)) > 1e-6) {
      return rule.step === 2 ? `${part} is not odd` : `${part} is not a multiple of ${rule.step}${unit}`;
    }
  }
  return '';
}

// A field that failed its check: its name as the message gives it, the problem, and the input
// that gets the focus.
export interface Refusal {
  label: string;
  problem: string;
  input: HTMLElement;
}

// Upload Settings of every panel: nothing is sent while a field is wrong (the first gets the
// focus) or when nothing changed; otherwise one PATCH of `body`, whose response and JSON answer
// come back for the page to show. Null when nothing was sent.
export async function patchSettings(
  name: string, body: Record<string, unknown>, wrong: Refusal[], message: HTMLElement,
): Promise<{ response: Response; answer: Record<string, unknown> & { error?: { message: string; field?: string } } } | null> {
  if (wrong.length > 0) {
    message.textContent = `Nothing sent: ${wrong.map((refusal) => `${refusal.label}: ${refusal.problem}`).join('; ')}`;
    message.dataset.state = 'error';
    wrong[0].input.focus();
    return null;
  }
  if (Object.keys(body).length === 0) {
    message.textContent = 'Nothing to upload: no field was changed.';
    message.dataset.state = '';
    return null;
  }
  message.textContent = `Uploading ${Object.keys(body).join(', ')}…`;
  message.dataset.state = '';
  const response = await authorisedFetch(`/api/sensors/${encodeURIComponent(name)}/settings`, {
    method: 'PATCH',
    headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify(body),
  });
  const answer = (await response.json()) as Record<string, unknown> & { error?: { message: string; field?: string } };
  return { response, answer };
}
