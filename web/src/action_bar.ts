// The actions of a sensor's family that its page does not place itself, a button per action and
// value of its argument, from GET /api/families: an action a family adds reaches its page unwritten.
import { loadFamilies, actionsOf } from './descriptors';
import { element } from './settings_fields';

// `run` does the action as the page does its own (its message line); `placed` are the page's own.
export class ActionBar {
  readonly root = element('div', 'buttons other-actions');

  constructor(private readonly family: string, private readonly placed: string[],
    private readonly run: (action: string, argument: string, label: string) => unknown) {
    this.root.setAttribute('aria-label', 'More actions');
    loadFamilies().then(() => this.build(), () => { /* the page says so when its own reads fail */ });
  }

  private build(): void {
    for (const action of actionsOf(this.family)) {
      if (this.placed.includes(action.name)) continue;
      const values = action.arguments.length === 0 || action.argument_optional ? ['', ...action.arguments] : action.arguments;
      for (const argument of values) {
        const label = `${action.name[0].toUpperCase()}${action.name.slice(1)}${argument ? ` ${argument}` : ''}`;
        const button = element('button', 'action', label);
        button.type = 'button';
        button.title = action.description;
        button.dataset.action = action.name;
        button.addEventListener('click', () => void this.run(action.name, argument, label));
        this.root.append(button);
      }
    }
  }
}
