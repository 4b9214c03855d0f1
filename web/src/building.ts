// The building on the map and in the mission panel: the lifts' doors, lobbies and cars on the floor the robot is on,
// the doors of its map coloured by what their controller says, the floor in the header, and a floor picker that sends
// the robot to a named place on any floor (the daemon rides the lifts).
import L from 'leaflet';

import { send, type Building, type Doors, type Place, type Pose } from './api';
import { byId, type Report } from './dom';
import { toLatLng } from './map_view';
import { permitted } from './session';

export class BuildingLayers {
  private readonly lifts = L.layerGroup();
  private readonly doors = L.layerGroup();
  private building: Building | null = null;
  private shownDoors = '';

  constructor(map: L.Map, private readonly report: Report) {
    this.lifts.addTo(map);
    this.doors.addTo(map);
    byId('floor-select').addEventListener('change', () => this.showPlaces());
    byId('floor-go').addEventListener('click', () => void this.go());
    window.addEventListener('corridor:doors-changed', () => void this.reloadDoors().catch(() => {}));
    window.addEventListener('corridor:building-changed', () => void this.reload().catch(() => {}));
  }

  // The building and the doors again (after a change of map: another floor).
  async reload(): Promise<void> {
    this.building = await send<Building>('GET', '/api/v1/building');
    this.showFloors();
    this.drawLifts();
    await this.reloadDoors();
  }

  async reloadDoors(): Promise<void> {
    const doors = await send<Doors>('GET', '/api/v1/doors');
    const key = JSON.stringify(doors.doors);
    if (key === this.shownDoors) return;
    this.shownDoors = key;
    this.doors.clearLayers();
    for (const d of doors.doors) {
      L.polyline([toLatLng(d.x1, d.y1), toLatLng(d.x2, d.y2)], {
        color: d.state === 'open' ? '#2ea043' : d.state === 'refused' || d.state === 'failed' ? '#f85149' : '#8250df',
        weight: 5, className: `door door-${d.state}`,
      }).bindTooltip(`door ${d.id} (${d.source}): ${d.state}`).addTo(this.doors);
    }
  }

  // The floor the robot is on, in the header.
  showFloor(floor: string | null): void {
    const badge = byId('floor');
    badge.hidden = floor === null;
    badge.textContent = floor === null ? '' : `floor ${floor}`;
  }

  private drawLifts(): void {
    this.lifts.clearLayers();
    const here = this.building?.floor;
    for (const lift of this.building?.lifts ?? []) {
      for (const stop of lift.stops) {
        if (stop.floor !== here) continue;
        L.polyline([toLatLng(stop.door.x1, stop.door.y1), toLatLng(stop.door.x2, stop.door.y2)],
          { color: '#bf3989', weight: 5, className: 'lift-door' }).bindTooltip(`lift ${lift.id}: its door`)
          .addTo(this.lifts);
        L.polygon(carCorners(stop.car, lift.car_depth_m, lift.car_width_m).map(([x, y]) => toLatLng(x, y)),
          { color: '#bf3989', weight: 1, fillOpacity: 0.15, className: 'lift-car' })
          .bindTooltip(`lift ${lift.id} (floors ${lift.stops.map((s) => s.floor).join(', ')})`).addTo(this.lifts);
        L.circleMarker(toLatLng(stop.lobby.x, stop.lobby.y), { radius: 5, color: '#bf3989', className: 'lift-lobby' })
          .bindTooltip(`lift ${lift.id}: where the robot waits`).addTo(this.lifts);
      }
    }
  }

  private showFloors(): void {
    const floors = this.building?.floors ?? [];
    byId('floor-picker').hidden = floors.length === 0;
    const select = byId<HTMLSelectElement>('floor-select');
    const chosen = select.value || this.building?.floor || '';
    select.replaceChildren(...floors.map((f) => new Option(f.name, f.name, false, f.name === chosen)));
    this.showPlaces();
  }

  private placesOf(floor: string): Place[] {
    return this.building?.floors.find((f) => f.name === floor)?.places ?? [];
  }

  private showPlaces(): void {
    const floor = byId<HTMLSelectElement>('floor-select').value;
    const places = this.placesOf(floor);
    byId<HTMLSelectElement>('floor-place').replaceChildren(...places.map((p) => new Option(p.name, p.name)));
    const go = byId<HTMLButtonElement>('floor-go');
    go.disabled = places.length === 0 || !permitted(go);
  }

  private async go(): Promise<void> {
    const floor = byId<HTMLSelectElement>('floor-select').value;
    const place = byId<HTMLSelectElement>('floor-place').value;
    try {
      await send('POST', '/api/v1/missions', { waypoints: [{ place, floor }] });
      this.report(`going to ${place} on floor ${floor}`);
    } catch (e) {
      this.report(e as Error);
    }
  }
}

// The car's corners: `car` its centre facing in, `depth` along that heading, `width` across.
function carCorners(car: Pose, depth: number, width: number): [number, number][] {
  const c = Math.cos(car.yaw);
  const s = Math.sin(car.yaw);
  return [[-1, -1], [1, -1], [1, 1], [-1, 1]].map(([u, v]) => {
    const x = (u * depth) / 2;
    const y = (v * width) / 2;
    return [car.x + c * x - s * y, car.y + s * x + c * y];
  });
}
