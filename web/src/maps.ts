// The map library in the console: the robot's maps listed, one chosen to work in, renamed, deleted, exported as
// map_server files (a zip of NAME.yaml and NAME.png) and imported from them (a .yaml with its image, or a zip of
// them). The daemon checks everything (GET/POST /api/v1/maps, PATCH/DELETE /api/v1/maps/{name},
// GET /api/v1/maps/{name}/files); a map it refuses keeps its reason in the report line.
import { strFromU8, strToU8, unzipSync, zipSync } from 'fflate';

import { send } from './api';
import { byId, type Report } from './dom';
import { applyNeeds, type Me } from './session';

interface Maps { maps: string[]; active: string; }
interface MapFiles { name: string; yaml: string; image_name: string; image: string; }

// A file chosen for import: its name and bytes.
interface Picked { name: string; bytes: Uint8Array; }

const kImageTypes = /\.(pgm|png|bmp|jpe?g|tiff?)$/i;

// Base64 of bytes, a chunk at a time (a map's image is megabytes: too long for one String.fromCharCode call).
function toBase64(bytes: Uint8Array): string {
  let text = '';
  for (let i = 0; i < bytes.length; i += 0x8000) text += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(text);
}

function fromBase64(text: string): Uint8Array {
  return Uint8Array.from(atob(text), (c) => c.charCodeAt(0));
}

const baseName = (path: string) => path.split(/[\\/]/).pop() ?? path;
const stem = (path: string) => baseName(path).replace(/\.[^.]*$/, '');

// The map_server YAML among the files (a zip's files count as chosen) and the image it names: the file of that name,
// or else the only image there is. Throws what is missing, in words.
export function pickMapFiles(files: Picked[]): { yaml: Picked; image: Picked } {
  const unpacked = files.flatMap((f) => /\.zip$/i.test(f.name)
    ? Object.entries(unzipSync(f.bytes)).filter(([name]) => !name.endsWith('/')).map(([name, bytes]) => ({ name, bytes }))
    : [f]);
  const yamls = unpacked.filter((f) => /\.ya?ml$/i.test(f.name));
  if (yamls.length !== 1) throw new Error(`choose one map_server .yaml (${yamls.length} given) with its image, or a zip`);
  const yaml = yamls[0]!;
  const named = /^image:\s*["']?([^"'\n#]+?)["']?\s*(#.*)?$/m.exec(strFromU8(yaml.bytes))?.[1];
  const images = unpacked.filter((f) => kImageTypes.test(f.name));
  const image = (named ? images.find((f) => baseName(f.name) === baseName(named)) : undefined)
    ?? (images.length === 1 ? images[0] : undefined);
  if (!image) throw new Error(named ? `the image '${named}' the .yaml names is not among the files` : 'no image given');
  return { yaml, image };
}

export class MapsPanel {
  private active = '';

  constructor(private readonly me: Me, private readonly report: Report) {
    const files = byId<HTMLInputElement>('maps-import-files');
    const name = byId<HTMLInputElement>('maps-import-name');
    // The name proposed is the yaml's (or the zip's), made a map name.
    files.addEventListener('change', () => {
      const first = [...(files.files ?? [])].find((f) => /\.(ya?ml|zip)$/i.test(f.name));
      if (first && !name.value) name.value = stem(first.name).replace(/[^A-Za-z0-9_.-]/g, '_').replace(/^[._]+/, '');
    });
    byId('maps-import').addEventListener('click', () => {
      void this.import([...(files.files ?? [])], name.value.trim()).then((done) => {
        if (!done) return;
        files.value = '';
        name.value = '';
      });
    });
  }

  async reload(): Promise<void> {
    this.show(await send<Maps>('GET', '/api/v1/maps'));
  }

  // The map in use changed (chosen here, elsewhere, or made by mapping).
  showActive(name: string): void {
    if (name !== this.active) void this.reload().catch((e: Error) => this.report(e));
  }

  private show(library: Maps): void {
    this.active = library.active;
    const list = byId('maps-list');
    list.replaceChildren(...library.maps.map((name) => this.row(name, name === library.active)));
    applyNeeds(this.me, list);
  }

  private row(name: string, active: boolean): HTMLLIElement {
    const li = document.createElement('li');
    li.dataset.map = name;
    li.className = active ? 'active' : '';
    const label = document.createElement('span');
    label.className = 'map-label';
    label.textContent = name;
    if (active) label.append(' ', Object.assign(document.createElement('em'), { textContent: 'in use' }));
    const buttons = document.createElement('span');
    buttons.className = 'buttons';
    const button = (text: string, needs: string | null, run: () => Promise<unknown>, title: string) => {
      const b = Object.assign(document.createElement('button'), { textContent: text, title });
      b.setAttribute('aria-label', `${text} map ${name}`);
      b.dataset.action = text.toLowerCase();
      if (needs) b.dataset.needs = needs;
      b.addEventListener('click', () => void run().catch((e: Error) => this.report(e)));
      buttons.append(b);
      return b;
    };
    button('Use', 'admin', () => this.use(name), 'Work in this map: localize, plan and show it').disabled = active;
    button('Rename', 'admin', async () => this.rename(li, name), 'Give the map another name');
    button('Export', null, () => this.export(name), 'Download the map as map_server files (zip)');
    button('Delete', 'admin', () => this.delete(name), 'Delete the map with its zones, places and doors');
    li.append(label, buttons);
    return li;
  }

  private async use(name: string): Promise<void> {
    await send('PUT', '/api/v1/map/active', { name });
    this.report(`working in map '${name}'`);
    await this.reload();
  }

  // The name becomes a field in place; Enter or OK renames, Escape or Cancel leaves it.
  private rename(li: HTMLLIElement, name: string): void {
    const field = Object.assign(document.createElement('input'), { value: name });
    field.setAttribute('aria-label', `new name for map ${name}`);
    const ok = Object.assign(document.createElement('button'), { textContent: 'OK' });
    const cancel = Object.assign(document.createElement('button'), { textContent: 'Cancel' });
    const form = document.createElement('span');
    form.className = 'buttons';
    form.append(field, ok, cancel);
    li.replaceChildren(form);
    field.focus();
    field.select();
    const submit = () => {
      send('PATCH', `/api/v1/maps/${encodeURIComponent(name)}`, { name: field.value.trim() })
        .then(() => { this.report(`map '${name}' renamed '${field.value.trim()}'`); return this.reload(); })
        .catch((e: Error) => { this.report(e); field.focus(); });
    };
    const leave = () => void this.reload().catch((e: Error) => this.report(e));
    ok.addEventListener('click', submit);
    cancel.addEventListener('click', leave);
    field.addEventListener('keydown', (e) => {
      if (e.key === 'Enter') submit();
      if (e.key === 'Escape') leave();
    });
  }

  private async delete(name: string): Promise<void> {
    if (!confirm(`Delete map '${name}' with its zones, places and doors?`)) return;
    await send('DELETE', `/api/v1/maps/${encodeURIComponent(name)}`);
    this.report(`map '${name}' deleted`);
    await this.reload();
  }

  private async export(name: string): Promise<void> {
    const files = await send<MapFiles>('GET', `/api/v1/maps/${encodeURIComponent(name)}/files`);
    const zip = zipSync({ [`${name}.yaml`]: strToU8(files.yaml), [files.image_name]: fromBase64(files.image) });
    const link = Object.assign(document.createElement('a'), {
      href: URL.createObjectURL(new Blob([zip as BlobPart], { type: 'application/zip' })),
      download: `${name}.zip`,
    });
    link.click();
    setTimeout(() => URL.revokeObjectURL(link.href), 60_000);  // once the download has surely read it
  }

  // Whether the map was imported (the report says why not).
  private async import(chosen: File[], name: string): Promise<boolean> {
    try {
      if (!name) throw new Error('give the imported map a name');
      const picked = await Promise.all(chosen.map(async (f) => ({ name: f.name, bytes: new Uint8Array(await f.arrayBuffer()) })));
      const { yaml, image } = pickMapFiles(picked);
      await send('POST', '/api/v1/maps', { name, yaml: strFromU8(yaml.bytes), image: toBase64(image.bytes) });
      this.report(`map '${name}' imported: choose Use to work in it`);
      await this.reload();
      return true;
    } catch (e) {
      this.report(e as Error);
      return false;
    }
  }
}
