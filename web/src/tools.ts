// The map tools: click a goal (drag for its heading) with a plan preview, waypoint missions, named places, zones
// (zones.ts), painting the map, and telling localization where the robot is (press on it, drag along its heading,
// as RViz's 2D Pose Estimate). One tool is active at a time; Pan gives the mouse back to the map.
import L from 'leaflet';

import { send, type PoseTaken, type Building, type Goal, type Place, type PlanResult } from './api';
import { byId, escapeHtml, type Report } from './dom';
import { toLatLng, type MapView } from './map_view';
import type { ZoneLayers } from './zones';

type Tool = 'pan' | 'goal' | 'set_pose' | 'waypoints' | 'keep_out' | 'speed_limit' | 'place' | 'dock_place' | 'door' | 'lift_stop' |
  'edit_zones' | 'delete_zones' | 'paint_occupied' | 'paint_free' | 'paint_unknown';

const kHeadingDragM = 0.15;  // a drag shorter than this sets no heading
const kPaintValue: Record<string, number> = { paint_occupied: 100, paint_free: 0, paint_unknown: -1 };

export class Tools {
  private tool: Tool = 'pan';
  private readonly preview = L.layerGroup();
  private goal: Goal | null = null;
  private waypoints: { x: number; y: number }[] = [];
  private press: L.LatLng | null = null;
  private strokes: { x0: number; y0: number; x1: number; y1: number; value: number }[] = [];
  private places: Place[] = [];

  constructor(private readonly view: MapView, private readonly zones: ZoneLayers,
    private readonly report: Report) {
    const map = view.map;
    this.preview.addTo(map);
    for (const button of document.querySelectorAll<HTMLButtonElement>('#tools button[data-tool]')) {
      button.addEventListener('click', () => this.select(button.dataset.tool as Tool));
    }
    // Pointer events on the map's element, so that a finger (or a pen) presses, drags a heading or paints as a mouse
    // does; one pointer at a time, and none that starts on a control over the map.
    const element = map.getContainer();
    let pointer: number | null = null;
    element.addEventListener('pointerdown', (e) => {
      if (pointer !== null || !e.isPrimary || !this.pointed() || (e.target as Element).closest('.leaflet-control')) return;
      pointer = e.pointerId;
      element.setPointerCapture(e.pointerId);
      this.down(map.mouseEventToLatLng(e));
    });
    element.addEventListener('pointermove', (e) => {
      if (e.pointerId === pointer) this.move(map.mouseEventToLatLng(e));
    });
    element.addEventListener('pointerup', (e) => {
      if (e.pointerId !== pointer) return;
      pointer = null;
      void this.up(map.mouseEventToLatLng(e));
    });
    element.addEventListener('pointercancel', (e) => {
      if (e.pointerId !== pointer) return;
      pointer = null;
      this.press = null;
      this.preview.clearLayers();
    });
    byId('plan-go').addEventListener('click', () => void this.go());
    byId('plan-clear').addEventListener('click', () => this.clear());
    byId('place-go').addEventListener('click', () => {
      const name = byId<HTMLSelectElement>('places').value;
      if (name) void this.startMission([{ place: name }]);
    });
    byId('place-delete').addEventListener('click', () => void this.deletePlace());
    byId('dock').addEventListener('click', () => void this.dock());
    byId('undock').addEventListener('click', () => {
      send('POST', '/api/v1/undock').then(() => this.report('undocking'), (e: Error) => this.report(e));
    });
  }

  // Docks at the dock picked in the places list, else at the nearest.
  private async dock(): Promise<void> {
    const picked = this.places.find((p) => p.name === byId<HTMLSelectElement>('places').value && p.kind === 'dock');
    try {
      await send('POST', '/api/v1/dock', picked ? { dock: picked.name } : {});
      this.report(`docking at ${picked ? `'${picked.name}'` : 'the nearest dock'}`);
    } catch (e) {
      this.report(e as Error);
    }
  }

  select(tool: Tool): void {
    this.zones.stopDrawing();
    this.zones.edit(false);
    this.zones.remove(false);
    this.clear();
    this.tool = tool;
    for (const b of document.querySelectorAll<HTMLButtonElement>('#tools button[data-tool]')) {
      b.classList.toggle('active', b.dataset.tool === tool);
    }
    const map = this.view.map;
    if (tool === 'pan' || tool === 'edit_zones' || tool === 'delete_zones') map.dragging.enable();
    else map.dragging.disable();
    // The browser leaves a finger's drags on the map to the tool (no scrolling, no zooming) while it takes them.
    map.getContainer().classList.toggle('pointer-tool', this.pointed());
    if (tool === 'keep_out' || tool === 'speed_limit') {
      this.zones.draw(tool, Number(byId<HTMLInputElement>('zone-speed').value) || 0.2);
    }
    if (tool === 'edit_zones') this.zones.edit(true);
    if (tool === 'delete_zones') this.zones.remove(true);
  }

  // Whether the tool takes the pointer's presses, drags and releases itself (Leaflet pans for the others, and the zone
  // tools have Geoman's).
  private pointed(): boolean {
    return !['pan', 'keep_out', 'speed_limit', 'edit_zones', 'delete_zones'].includes(this.tool);
  }

  async reloadPlaces(): Promise<void> {
    this.places = (await send<{ places: Place[] }>('GET', '/api/v1/places')).places;
    const select = byId<HTMLSelectElement>('places');
    select.replaceChildren(...this.places.map((p) => new Option(p.name, p.name)));
    this.placeLayer.clearLayers();
    for (const p of this.places) {
      const symbol = p.kind === 'dock' ? '&#9889;' : '&#9873;';
      L.marker(toLatLng(p.x, p.y), {
        icon: L.divIcon({ className: `place-label ${p.kind}`, html: `${symbol} ${escapeHtml(p.name)}`, iconSize: [80, 16],
          iconAnchor: [6, 14] }),
      }).addTo(this.placeLayer);
      if (p.kind === 'dock') {
        // Which way the robot faces on it, and where it stops before docking.
        const ahead = toLatLng(p.x + 0.3 * Math.cos(p.yaw), p.y + 0.3 * Math.sin(p.yaw));
        L.polyline([toLatLng(p.x, p.y), ahead], { color: '#d29922', weight: 3 }).addTo(this.placeLayer);
        if (p.staging) {
          L.polyline([toLatLng(p.staging.x, p.staging.y), toLatLng(p.x, p.y)], { color: '#d29922', weight: 1, dashArray: '3 4' })
            .addTo(this.placeLayer);
        }
      }
    }
  }

  private readonly placeLayer = L.layerGroup();

  attachPlaces(): void {
    this.placeLayer.addTo(this.view.map);
  }

  private down(at: L.LatLng): void {
    if (this.tool === 'goal' || this.tool === 'set_pose' || this.tool === 'dock_place' || this.tool === 'door' ||
      this.tool === 'lift_stop') {
      this.press = at;
      this.goal = null;
      this.preview.clearLayers();
    } else if (this.tool.startsWith('paint_')) {
      this.press = at;
      this.strokes = [];
      this.paint(at);
    }
  }

  private move(at: L.LatLng): void {
    if (!this.press) return;
    if (this.tool === 'door' || this.tool === 'lift_stop') {
      this.preview.clearLayers();
      L.polyline([this.press, at], { color: this.tool === 'door' ? '#8250df' : '#bf3989', weight: 5, dashArray: '4 4' })
        .addTo(this.preview);
    } else if (this.tool === 'goal' || this.tool === 'set_pose' || this.tool === 'dock_place') {
      const color = this.tool === 'goal' ? '#2ea043' : '#d29922';
      this.preview.clearLayers();
      L.circleMarker(this.press, { radius: 6, color }).addTo(this.preview);
      if (this.press.distanceTo(at) > kHeadingDragM) L.polyline([this.press, at], { color, weight: 3 }).addTo(this.preview);
    } else if (this.tool.startsWith('paint_')) {
      this.paint(at);
    }
  }

  private async up(at: L.LatLng): Promise<void> {
    const press = this.press;
    this.press = null;
    if (this.tool === 'goal' && press) {
      const goal: Goal = { x: press.lng, y: press.lat };
      if (press.distanceTo(at) > kHeadingDragM) goal.yaw = Math.atan2(at.lat - press.lat, at.lng - press.lng);
      this.goal = goal;
      await this.previewPlan(goal);
    } else if (this.tool === 'set_pose' && press) {
      await this.setPose(press, at);
    } else if (this.tool === 'dock_place' && press) {
      await this.addDock(press, at);
    } else if (this.tool === 'door' && press) {
      await this.addDoor(press, at);
    } else if (this.tool === 'lift_stop' && press) {
      await this.addLiftStop(press, at);
    } else if (this.tool === 'waypoints') {
      this.waypoints.push({ x: at.lng, y: at.lat });
      L.marker(at, { icon: L.divIcon({ className: 'place-label', html: `${this.waypoints.length}`, iconSize: [16, 16] }) })
        .addTo(this.preview);
      this.showBar(`${this.waypoints.length} waypoint(s)`);
    } else if (this.tool === 'place') {
      const name = window.prompt('Name of this place');
      if (!name) return;
      try {
        await send<Place>('POST', '/api/v1/places', { name, x: at.lng, y: at.lat, yaw: 0 });
        this.report(`place '${name}' added`);
        await this.reloadPlaces();
      } catch (e) {
        this.report(e as Error);
      }
    } else if (this.tool.startsWith('paint_') && press) {
      await this.flushPaint();
    }
  }

  private async setPose(press: L.LatLng, at: L.LatLng): Promise<void> {
    this.preview.clearLayers();
    if (press.distanceTo(at) <= kHeadingDragM) {
      this.report('set pose: press where the robot is and drag the way it faces');
      return;
    }
    const pose = { x: press.lng, y: press.lat, yaw: Math.atan2(at.lat - press.lat, at.lng - press.lng) };
    try {
      const taken = await send<PoseTaken>('PUT', '/api/v1/localization/pose', pose);
      const where = `pose x ${pose.x.toFixed(2)} m, y ${pose.y.toFixed(2)} m`;
      // Taken either way; when the scan contradicts it, say so as a warning: localization will likely move it back.
      this.report(taken.agrees ? `${where} ${taken.detail}` : new Error(`${where} ${taken.detail}`));
    } catch (e) {
      this.report(e as Error);
    }
  }

  private async previewPlan(goal: Goal): Promise<void> {
    try {
      const plan = await send<PlanResult>('POST', '/api/v1/plan', { goal });
      L.polyline(plan.path.map((p) => toLatLng(p.x, p.y)), { color: '#2ea043', weight: 3, dashArray: '6 6',
        className: 'plan-preview' }).addTo(this.preview);
      this.showBar(`${plan.length_m.toFixed(1)} m, clearance ≥ ${plan.min_clearance_m.toFixed(2)} m ` +
        `(mean ${plan.mean_clearance_m.toFixed(2)} m), planned in ${plan.planning_ms.toFixed(0)} ms`);
    } catch (e) {
      this.showBar((e as Error).message, false);
    }
  }

  private showBar(text: string, canGo = true): void {
    byId('plan-summary').textContent = text;
    byId<HTMLButtonElement>('plan-go').disabled = !canGo;
    byId('plan-bar').classList.remove('hidden');
  }

  private clear(): void {
    this.preview.clearLayers();
    this.goal = null;
    this.waypoints = [];
    byId('plan-bar').classList.add('hidden');
  }

  private async go(): Promise<void> {
    const goals: Goal[] = this.tool === 'waypoints' ? this.waypoints : this.goal ? [this.goal] : [];
    if (goals.length > 0) await this.startMission(goals);
  }

  private async startMission(waypoints: Goal[]): Promise<void> {
    try {
      await send('POST', '/api/v1/missions', { waypoints });
      this.clear();
      this.report('mission started');
    } catch (e) {
      this.report(e as Error);
    }
  }

  // A door across a passage, from where the press was to where it was let go; its id is the controller's name for it.
  private async addDoor(press: L.LatLng, at: L.LatLng): Promise<void> {
    this.preview.clearLayers();
    const id = window.prompt('Id of this door (as its controller knows it)');
    if (!id) return;
    try {
      await send('POST', '/api/v1/doors', { id, x1: press.lng, y1: press.lat, x2: at.lng, y2: at.lat });
      this.report(`door '${id}' added`);
      window.dispatchEvent(new Event('corridor:doors-changed'));
    } catch (e) {
      this.report(e as Error);
    }
  }

  // A lift's door on the floor the robot is on, from the press to where it was let go; the lobby stands 0.8 m out
  // from its middle on the right of the drag, facing it.
  private async addLiftStop(press: L.LatLng, at: L.LatLng): Promise<void> {
    this.preview.clearLayers();
    const dx = at.lng - press.lng;
    const dy = at.lat - press.lat;
    const length = Math.hypot(dx, dy);
    if (length < 0.3) {
      this.report('a lift door is 0.3 m wide at least: drag from one side of it to the other');
      return;
    }
    const id = window.prompt('Id of the lift (as its controller knows it)');
    if (!id) return;
    const [nx, ny] = [dy / length, -dx / length];  // the right of the drag
    const lobby = { x: (press.lng + at.lng) / 2 + 0.8 * nx, y: (press.lat + at.lat) / 2 + 0.8 * ny,
      yaw: Math.atan2(-ny, -nx) };
    try {
      const { floor } = await send<Building>('GET', '/api/v1/building');
      if (!floor) throw new Error('the map in use is no floor of the building');
      await send('PUT', `/api/v1/building/lifts/${encodeURIComponent(id)}/stops/${encodeURIComponent(floor)}`,
        { x1: press.lng, y1: press.lat, x2: at.lng, y2: at.lat, lobby });
      this.report(`lift '${id}' stops on floor ${floor}`);
      window.dispatchEvent(new Event('corridor:building-changed'));
    } catch (e) {
      this.report(e as Error);
    }
  }

  // A dock where the robot stands on it (press), facing the way dragged.
  private async addDock(press: L.LatLng, at: L.LatLng): Promise<void> {
    this.preview.clearLayers();
    const yaw = Math.atan2(at.lat - press.lat, at.lng - press.lng);
    if (press.distanceTo(at) <= kHeadingDragM) {
      this.report('drag from where the robot stands on the dock towards the dock');
      return;
    }
    const name = window.prompt('Name of this dock', 'dock');
    if (!name) return;
    try {
      await send<Place>('POST', '/api/v1/places', { name, x: press.lng, y: press.lat, yaw, kind: 'dock' });
      this.report(`dock '${name}' added`);
      await this.reloadPlaces();
    } catch (e) {
      this.report(e as Error);
    }
  }

  private async deletePlace(): Promise<void> {
    const place = this.places.find((p) => p.name === byId<HTMLSelectElement>('places').value);
    if (!place) return;
    await send('DELETE', `/api/v1/places/${place.id}`).catch((e: Error) => this.report(e));
    await this.reloadPlaces();
  }

  // One brush dab: a square of brush x brush cells around the point, shown at once and sent on release.
  private paint(at: L.LatLng): void {
    const cell = this.view.cellAt(at.lng, at.lat);
    if (!cell) return;
    const half = Math.floor((Number(byId<HTMLInputElement>('brush').value) || 1) / 2);
    const value = kPaintValue[this.tool];
    const rect = { x0: cell.col - half, y0: cell.row - half, x1: cell.col + half, y1: cell.row + half, value };
    const last = this.strokes[this.strokes.length - 1];
    if (last && last.x0 === rect.x0 && last.y0 === rect.y0) return;
    this.strokes.push(rect);
    const colour = value === 100 ? '#000' : value === 0 ? '#fff' : '#999';
    const r = 0.05 * (half + 0.5);
    L.rectangle([[at.lat - r, at.lng - r], [at.lat + r, at.lng + r]], { color: colour, weight: 0, fillOpacity: 0.8 })
      .addTo(this.preview);
  }

  private async flushPaint(): Promise<void> {
    if (this.strokes.length === 0) return;
    const { width, height } = this.view.size;
    const rects = this.strokes.map((r) => ({ ...r, x0: Math.max(0, r.x0), y0: Math.max(0, r.y0),
      x1: Math.min(width - 1, r.x1), y1: Math.min(height - 1, r.y1) }));
    this.strokes = [];
    try {
      await send('PUT', '/api/v1/map/cells', { rects });
      this.report('map edited');
    } catch (e) {
      this.report(e as Error);
    }
    // The new map image replaces the preview when the state reports the new revision.
  }

  clearPaintPreview(): void {
    if (this.tool.startsWith('paint_')) this.preview.clearLayers();
  }
}
