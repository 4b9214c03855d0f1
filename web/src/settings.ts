// The settings page at /settings: the configuration file edited in the browser, a field per key, generated from the
// configuration's schema (GET /api/v1/config/schema: what the daemon's own checking code reads, with each key's type,
// default, range, choices, unit and help). Save sends the changed keys as one JSON merge patch (PATCH /api/v1/config);
// the daemon checks the whole file as at start-up and names the key it refuses, shown by that key's field. What the
// file holds but the running daemon does not (the `pending` keys) is marked: it takes effect at the next start.
// For admins; anyone else is sent to the console.
import { send } from './api';
import { byId } from './dom';
import { requireAdmin } from './session';

interface Field {
  path: string; type: 'boolean' | 'integer' | 'number' | 'string'; default: unknown;
  min?: number; max?: number; choices?: string[]; unit: string; help: string;
}
interface Schema { fields: Field[]; sections: Record<string, string>; }
interface ConfigFile { file: string; config: Record<string, unknown>; pending: string[]; changed?: string[]; }

// A dotted path's keys; a list's item (key[i]) is the key then the index.
function keysOf(path: string): (string | number)[] {
  return path.split('.').flatMap((part) => {
    const item = /^(.*)\[(\d+)\]$/.exec(part);
    return item ? [item[1]!, Number(item[2])] : [part];
  });
}

function valueAt(document: unknown, path: string): unknown {
  let at: unknown = document;
  for (const key of keysOf(path)) {
    if (at === null || typeof at !== 'object') return undefined;
    at = (at as Record<string | number, unknown>)[key];
  }
  return at;
}

// The merge patch that sets each path to its value (null: removed, so back to its default).
function patchOf(changes: Map<string, unknown>): Record<string, unknown> {
  const patch: Record<string, unknown> = {};
  for (const [path, value] of changes) {
    const keys = path.split('.');
    let at = patch;
    for (const key of keys.slice(0, -1)) at = (at[key] ??= {}) as Record<string, unknown>;
    at[keys[keys.length - 1]!] = value;
  }
  return patch;
}

const describe = (value: unknown) => (value === '' ? '""' : JSON.stringify(value));

class SettingsPage {
  private schema: Schema = { fields: [], sections: {} };
  private file: ConfigFile = { file: '', config: {}, pending: [] };
  private readonly changes = new Map<string, unknown>();
  private readonly open = new Set<string>();

  async load(): Promise<void> {
    [this.schema, this.file] = await Promise.all([send<Schema>('GET', '/api/v1/config/schema'),
      send<ConfigFile>('GET', '/api/v1/config')]);
    this.render();
  }

  start(): void {
    byId('settings-save').addEventListener('click', () => void this.save());
    byId('settings-discard').addEventListener('click', () => {
      this.changes.clear();
      this.status('');
      this.render();
    });
    byId<HTMLInputElement>('settings-search').addEventListener('input', () => this.filter());
  }

  private status(text: string, error = false): void {
    const status = byId('settings-status');
    status.textContent = text;
    status.className = error ? 'error' : 'muted';
  }

  private render(): void {
    byId('settings-file').textContent = this.file.file;
    const pending = byId('settings-pending');
    pending.hidden = this.file.pending.length === 0;
    pending.textContent = `At the next start: ${this.file.pending.join(', ')}`;
    const sections = new Map<string, Field[]>();
    for (const field of this.schema.fields) {
      const section = field.path.split('.')[0]!;
      if (!sections.has(section)) sections.set(section, []);
      sections.get(section)!.push(field);
    }
    const container = byId('settings-sections');
    container.replaceChildren(...[...sections].map(([name, fields]) => this.section(name, fields)));
    this.filter();
    this.updateButtons();
  }

  private section(name: string, fields: Field[]): HTMLDetailsElement {
    const details = document.createElement('details');
    details.className = 'panel settings-section';
    details.dataset.section = name;
    details.open = this.open.has(name);
    details.addEventListener('toggle', () => (details.open ? this.open.add(name) : this.open.delete(name)));
    const summary = document.createElement('summary');
    summary.textContent = name;
    details.append(summary);
    if (this.schema.sections[name]) {
      details.append(Object.assign(document.createElement('p'), { className: 'muted help', textContent: this.schema.sections[name] }));
    }
    for (const field of fields) details.append(this.row(field, name));
    return details;
  }

  private row(field: Field, section: string): HTMLDivElement {
    const id = `setting-${field.path.replace(/[^A-Za-z0-9]/g, '-')}`;
    const row = document.createElement('div');
    row.className = 'setting';
    row.dataset.path = field.path;
    const label = document.createElement('label');
    label.htmlFor = id;
    label.textContent = field.path.slice(section.length + 1);
    if (field.unit) label.append(' ', Object.assign(document.createElement('span'), { className: 'unit', textContent: `(${field.unit})` }));
    const stored = valueAt(this.file.config, field.path);
    const shown = this.changes.has(field.path) ? this.changes.get(field.path) : stored;
    const inList = field.path.includes('[');
    const input = this.input(field, id, shown ?? null);
    input.disabled = inList;  // a list is changed whole, in the file
    input.addEventListener(field.type === 'boolean' || field.choices ? 'change' : 'input', () => {
      this.change(field, this.read(field, input), stored);
      row.classList.toggle('changed', this.changes.has(field.path));
      this.clearError(row);
    });
    const notes = [field.help, `default ${describe(field.default)}`];
    if (field.min !== undefined && field.max !== undefined) notes.push(`from ${field.min} to ${field.max}`);
    if (inList) notes.push('in a list: edit it in the file');
    const help = Object.assign(document.createElement('small'), { className: 'help', id: `${id}-help`, textContent: notes.filter(Boolean).join(' · ') });
    input.setAttribute('aria-describedby', `${id}-help ${id}-error`);
    const error = Object.assign(document.createElement('small'), { className: 'error', id: `${id}-error` });
    const tags = document.createElement('span');
    tags.className = 'tags';
    if (this.file.pending.includes(field.path)) {
      tags.append(Object.assign(document.createElement('span'), { className: 'pending-tag', textContent: 'at next start' }));
    }
    if (stored !== undefined && !inList) {
      const reset = Object.assign(document.createElement('button'), { type: 'button', textContent: 'Default', title: 'Remove the key: back to its default' });
      reset.setAttribute('aria-label', `${field.path}: back to the default`);
      reset.addEventListener('click', () => {
        this.change(field, null, stored);
        row.classList.toggle('changed', this.changes.has(field.path));
        this.setInput(field, input, null);
      });
      tags.append(reset);
    }
    row.classList.toggle('changed', this.changes.has(field.path));
    row.append(label, input, tags, help, error);
    return row;
  }

  private input(field: Field, id: string, value: unknown): HTMLInputElement | HTMLSelectElement {
    let input: HTMLInputElement | HTMLSelectElement;
    if (field.choices) {
      input = document.createElement('select');
      for (const choice of field.choices) input.append(new Option(choice, choice));
    } else {
      input = document.createElement('input');
      if (field.type === 'boolean') input.type = 'checkbox';
      if (field.type === 'integer' || field.type === 'number') {
        input.type = 'number';
        input.step = field.type === 'integer' ? '1' : 'any';
        if (field.min !== undefined) input.min = String(field.min);
        if (field.max !== undefined) input.max = String(field.max);
      }
    }
    input.id = id;
    this.setInput(field, input, value);
    return input;
  }

  // Shows `value` (null: the key is absent, so its default).
  private setInput(field: Field, input: HTMLInputElement | HTMLSelectElement, value: unknown): void {
    const effective = value ?? field.default;
    if (input instanceof HTMLInputElement && input.type === 'checkbox') {
      input.checked = Boolean(effective);
    } else if (input instanceof HTMLSelectElement) {
      input.value = String(effective);
    } else {
      input.value = value === null ? '' : String(value);
      input.placeholder = field.default === null || field.default === undefined ? '' : String(field.default);
    }
  }

  // What the field says now: null for an emptied number (the default), the text for anything the daemon will check.
  private read(field: Field, input: HTMLInputElement | HTMLSelectElement): unknown {
    if (input instanceof HTMLInputElement && input.type === 'checkbox') return input.checked;
    if (field.type === 'integer' || field.type === 'number') {
      if (input.value.trim() === '') return null;
      const number = Number(input.value);
      return Number.isFinite(number) ? number : input.value;
    }
    return input.value;
  }

  private change(field: Field, value: unknown, stored: unknown): void {
    if (JSON.stringify(value) === JSON.stringify(stored ?? null)) {
      this.changes.delete(field.path);
    } else {
      this.changes.set(field.path, value);
    }
    this.updateButtons();
  }

  private updateButtons(): void {
    byId<HTMLButtonElement>('settings-save').disabled = this.changes.size === 0;
    byId<HTMLButtonElement>('settings-discard').disabled = this.changes.size === 0;
    if (this.changes.size > 0) this.status(`${this.changes.size} unsaved change${this.changes.size === 1 ? '' : 's'}`);
  }

  private clearError(row: HTMLElement): void {
    row.querySelector('.error')!.textContent = '';
    row.querySelector('input, select')?.removeAttribute('aria-invalid');
  }

  private async save(): Promise<void> {
    try {
      const saved = await send<ConfigFile & { detail: string }>('PATCH', '/api/v1/config', patchOf(this.changes));
      this.changes.clear();
      this.file = saved;
      // A driver chosen anew brings its own keys.
      this.schema = await send<Schema>('GET', '/api/v1/config/schema');
      this.render();
      this.status(saved.changed && saved.changed.length > 0
        ? `Saved ${saved.changed.join(', ')}: takes effect at the next start` : 'Nothing changed');
    } catch (e) {
      this.showRefusal((e as Error).message);
    }
  }

  // The daemon's refusal ("<title>: <file>: <key path>: <why>") by the field of the key it names.
  private showRefusal(message: string): void {
    const detail = message.replace(/^[^:]*: /, '').replace(`${this.file.file}: `, '');
    const named = /^([A-Za-z0-9_.[\]-]+): ([\s\S]*)$/.exec(detail);
    const row = named ? [...document.querySelectorAll<HTMLElement>('.setting')].find((r) => r.dataset.path === named[1]) : undefined;
    this.status(`Not saved: ${detail}`, true);
    if (!row || !named) return;
    const details = row.closest('details');
    if (details) details.open = true;
    row.querySelector('.error')!.textContent = named[2]!;
    const input = row.querySelector<HTMLElement>('input, select');
    input?.setAttribute('aria-invalid', 'true');
    input?.focus();
  }

  // Shows the settings whose path or help has the words searched for, their sections opened.
  private filter(): void {
    const words = byId<HTMLInputElement>('settings-search').value.trim().toLowerCase();
    for (const details of document.querySelectorAll<HTMLDetailsElement>('.settings-section')) {
      let any = false;
      for (const row of details.querySelectorAll<HTMLElement>('.setting')) {
        const match = !words || (row.textContent ?? '').toLowerCase().includes(words);
        row.hidden = !match;
        any ||= match;
      }
      details.hidden = !any;
      if (words && any) details.open = true;
    }
  }
}

async function main(): Promise<void> {
  if (!(await requireAdmin())) return;
  const page = new SettingsPage();
  page.start();
  await page.load().catch((e: Error) => {
    byId('settings-status').textContent = `Settings unavailable: ${e.message}`;
  });
}

void main();
