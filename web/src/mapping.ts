// Mapping a new building from the console: a name, then Start (drive the robot round yourself) or Explore (it
// drives to the frontiers by itself), and Stop to save. While mapping, the map view shows the map as it is built,
// growing every few seconds; once saved it is the active map and the view returns to it (main.ts follows the
// active map's revision).
import { send, type MapInfo, type Mapping } from './api';
import { byId, type Report } from './dom';
import type { MapView } from './map_view';
import { repeat } from './poll';

const kPollMs = 1000;

export class MappingPanel {
  private shownRevision = -1;
  private wasActive = false;

  constructor(private readonly view: MapView, private readonly report: Report,
    private readonly showActiveMap: () => void) {
    const name = byId<HTMLInputElement>('mapping-name');
    const post = (path: string, body?: unknown) => {
      send('POST', path, body).then(() => this.poll()).catch((e: Error) => this.report(e));
    };
    byId('mapping-start').addEventListener('click', () => post('/api/v1/mapping/start', { name: name.value.trim() }));
    byId('mapping-explore').addEventListener('click', () => {
      // Within the mapping under way, or under the name given.
      post('/api/v1/mapping/explore', this.wasActive ? {} : { name: name.value.trim() });
    });
    byId('mapping-stop').addEventListener('click', () => post('/api/v1/mapping/stop'));
    repeat(() => this.poll(), kPollMs, (e) => { byId('mapping-status').textContent = `unavailable: ${e.message}`; });
  }

  private async poll(): Promise<void> {
    this.show(await send<Mapping>('GET', '/api/v1/mapping'));
  }

  private show(m: Mapping): void {
    const status = byId('mapping-status');
    if (m.active) {
      status.textContent = `${m.exploring ? 'exploring' : 'mapping'} '${m.name}': ${m.scans} scans, ${m.submaps} ` +
        `submaps, ${m.loop_closures} loop closures${m.error ? ` (${m.error})` : ''}`;
    } else if (m.saved) {
      status.textContent = `'${m.saved}' saved and in use`;
    } else {
      status.textContent = m.error ? `not mapping: ${m.error}` : 'not mapping';
    }
    byId<HTMLButtonElement>('mapping-start').disabled = m.active;
    byId<HTMLButtonElement>('mapping-stop').disabled = !m.active;
    byId<HTMLButtonElement>('mapping-explore').disabled = m.exploring;
    byId('map-area').classList.toggle('mapping', m.active);
    // The map as built so far, each new rendering.
    if (m.active && m.map && m.map.revision !== this.shownRevision) {
      this.shownRevision = m.map.revision;
      const info: MapInfo = { ...m.map, name: m.name };
      this.view.setMap(info);
    }
    if (this.wasActive && !m.active) {
      this.shownRevision = -1;
      this.showActiveMap();  // the map saved, or the one in use if saving failed
    }
    this.wasActive = m.active;
  }
}
