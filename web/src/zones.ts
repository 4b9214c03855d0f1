// Zones on the map, drawn, moved and deleted with Leaflet-Geoman; every change goes to the API at once, where plans
// and missions respect it. Keep-out zones are red, slow zones orange with their speed.
import '@geoman-io/leaflet-geoman-free';
import L from 'leaflet';

import type { Report } from './dom';
import { send, type Zone } from './api';
import { toLatLng } from './map_view';

type ZoneLayer = L.Polygon & { zone?: Zone };

export class ZoneLayers {
  private readonly group = L.featureGroup();

  constructor(private readonly map: L.Map, private readonly report: Report) {
    this.group.addTo(map);
    // Only zones are editable: everything else on the map (robot, path) stays out of Geoman's reach.
    L.PM.setOptIn(true);
    map.on('pm:create', (e) => void this.created(e.layer as L.Polygon));
    map.on('pm:remove', (e) => void this.removed(e.layer as ZoneLayer));
  }

  async reload(): Promise<void> {
    const { zones } = await send<{ zones: Zone[] }>('GET', '/api/v1/zones');
    this.group.clearLayers();
    for (const zone of zones) this.add(zone);
    // Geoman's global modes take the layers there when they were turned on: zones shown since (one put back with
    // Undo) join the mode in use.
    if (this.map.pm.globalRemovalModeEnabled()) {
      this.map.pm.disableGlobalRemovalMode();
      this.map.pm.enableGlobalRemovalMode();
    }
    if (this.map.pm.globalEditModeEnabled()) {
      this.map.pm.disableGlobalEditMode();
      this.edit(true);
    }
  }

  // Starts drawing a zone of `kind`; the polygon closes on a click of its first point.
  draw(kind: Zone['kind'], speed: number): void {
    this.drawing = { kind, speed };
    this.map.pm.enableDraw('Polygon', { allowSelfIntersection: false, pathOptions: this.style(kind) });
  }

  edit(on: boolean): void {
    if (on) this.map.pm.enableGlobalEditMode({ draggable: true, allowSelfIntersection: false });
    else this.map.pm.disableGlobalEditMode();
  }

  remove(on: boolean): void {
    if (on) this.map.pm.enableGlobalRemovalMode();
    else this.map.pm.disableGlobalRemovalMode();
  }

  stopDrawing(): void {
    this.drawing = null;
    this.map.pm.disableDraw();
  }

  private drawing: { kind: Zone['kind']; speed: number } | null = null;

  private style(kind: Zone['kind']): L.PathOptions {
    return kind === 'keep_out'
      ? { color: '#f85149', fillColor: '#f85149', fillOpacity: 0.35, weight: 2, className: 'zone keep-out' }
      : { color: '#d29922', fillColor: '#d29922', fillOpacity: 0.25, weight: 2, className: 'zone speed-limit' };
  }

  private add(zone: Zone): void {
    const layer: ZoneLayer = L.polygon(zone.polygon.map(([x, y]) => toLatLng(x, y)),
      { ...this.style(zone.kind), pmIgnore: false });
    layer.zone = zone;
    layer.bindTooltip(zone.kind === 'keep_out' ? `${zone.name || 'no-go'}`
      : `${zone.name || 'slow'}: ${zone.max_speed_mps} m/s`);
    layer.on('pm:edit', () => void this.changed(layer));
    layer.on('pm:dragend', () => void this.changed(layer));
    layer.addTo(this.group);
  }

  private polygonOf(layer: L.Polygon): [number, number][] {
    const rings = layer.getLatLngs() as L.LatLng[][];
    return rings[0].map((p) => [p.lng, p.lat]);
  }

  private async created(layer: L.Polygon): Promise<void> {
    const drawing = this.drawing;
    layer.remove();  // drawn by Geoman; shown again from the API's answer
    if (!drawing) return;
    const body: Omit<Zone, 'id'> = {
      name: drawing.kind === 'keep_out' ? 'no-go' : 'slow', kind: drawing.kind, polygon: this.polygonOf(layer) };
    if (drawing.kind === 'speed_limit') body.max_speed_mps = drawing.speed;
    try {
      await send<Zone>('POST', '/api/v1/zones', body);
      this.report(drawing.kind === 'keep_out' ? 'no-go zone added' : `slow zone added (${drawing.speed} m/s)`);
    } catch (e) {
      this.report(e as Error);
    }
    await this.reload();
    if (this.drawing) this.draw(this.drawing.kind, this.drawing.speed);  // ready for the next one
  }

  private async changed(layer: ZoneLayer): Promise<void> {
    if (!layer.zone) return;
    try {
      await send<Zone>('PUT', `/api/v1/zones/${layer.zone.id}`, { ...layer.zone, polygon: this.polygonOf(layer) });
      this.report('zone moved');
    } catch (e) {
      this.report(e as Error);
      await this.reload();
    }
  }

  // One click deletes (the Delete zone tool is chosen on purpose); the message offers to put the zone back.
  private async removed(layer: ZoneLayer): Promise<void> {
    const zone = layer.zone;
    if (!zone) return;
    try {
      await send<null>('DELETE', `/api/v1/zones/${zone.id}`);
      this.report(`zone '${zone.name}' deleted`, { label: 'Undo', run: () => void this.restore(zone) });
    } catch (e) {
      this.report(e as Error);
      await this.reload();
    }
  }

  private async restore(zone: Zone): Promise<void> {
    const { id: _, ...body } = zone;
    try {
      await send<Zone>('POST', '/api/v1/zones', body);
      await this.reload();  // on the map (and in the tool's mode) before it is said to be back
      this.report(`zone '${zone.name}' restored`);
    } catch (e) {
      this.report(e as Error);
      await this.reload();
    }
  }
}
