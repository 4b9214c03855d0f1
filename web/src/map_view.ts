// The map with pan and zoom (Leaflet, in metres: CRS.Simple with lat = y and lng = x of the map frame), the robot
// as its footprint and heading, its recent trail, the laser's latest scan, the simulator's ground truth as a faint
// ghost (with its people and the obstacles it adds to the world), and the mission's path and waypoints.
import L from 'leaflet';

import type { Detection, FleetOrder, MapInfo, Mission, Pose, SimObstacle, SimPerson, TrackedObject } from './api';

const kTrailLength = 600;
// An empty (transparent) image for overlays with nothing to show.
const kNoImage = 'data:image/gif;base64,R0lGODlhAQABAIAAAAAAAP///yH5BAEAAAAALAAAAAABAAEAAAIBRAA7';

export const toLatLng = (x: number, y: number): L.LatLng => L.latLng(y, x);

export class MapView {
  readonly map: L.Map;
  private info: MapInfo;
  private readonly image: L.ImageOverlay;
  private readonly footprint: L.Circle;
  private readonly heading: L.Polyline;
  private readonly ghost: L.Circle;
  private readonly trail: L.Polyline;
  private readonly missionPath: L.Polyline;
  private readonly missionGoals = L.layerGroup();
  private readonly fleetOrder = L.layerGroup();
  private shownFleetOrder = '';
  private readonly deadEnds = L.layerGroup();
  private readonly people = L.layerGroup();
  private readonly simPeople = L.layerGroup();
  private readonly tracked = L.layerGroup();
  private readonly simObstacles = L.layerGroup();
  private readonly traffic: L.ImageOverlay;
  private trafficAt = 0;
  private shownObstacles = '';
  private followed = false;
  // The scan's points on a canvas of their own: a few hundred markers redrawn twice a second.
  private readonly scan = L.layerGroup();
  private readonly scanRenderer = L.canvas({ padding: 0.2 });

  constructor(element: HTMLElement, info: MapInfo, private readonly footprintRadius: number) {
    this.info = info;
    this.map = L.map(element, { crs: L.CRS.Simple, minZoom: -3, maxZoom: 7, zoomSnap: 0.25, attributionControl: false });
    this.image = L.imageOverlay(info.image_url, this.bounds(info), { className: 'map-image' }).addTo(this.map);
    // Where people have been walking (the planner's traffic costs), over the map; hidden while there is none.
    this.traffic = L.imageOverlay(kNoImage, this.bounds(info), { className: 'traffic-image', opacity: 0 })
      .addTo(this.map);
    this.traffic.on('load', () => this.traffic.setOpacity(1));
    this.traffic.on('error', () => this.traffic.setOpacity(0));
    this.map.fitBounds(this.bounds(info));
    this.trail = L.polyline([], { color: '#58a6ff', weight: 2, opacity: 0.6, className: 'robot-trail' }).addTo(this.map);
    this.missionPath = L.polyline([], { color: '#2ea043', weight: 4, opacity: 0.8, className: 'mission-path' })
      .addTo(this.map);
    this.missionGoals.addTo(this.map);
    this.fleetOrder.addTo(this.map);
    this.deadEnds.addTo(this.map);
    this.people.addTo(this.map);
    this.simObstacles.addTo(this.map);
    this.simPeople.addTo(this.map);
    this.tracked.addTo(this.map);
    this.scan.addTo(this.map);
    this.ghost = L.circle([0, 0], { radius: footprintRadius, color: '#888', weight: 1, fill: false, dashArray: '3',
      className: 'robot-truth' });
    this.footprint = L.circle([0, 0], { radius: footprintRadius, color: '#1f6feb', weight: 2, fillOpacity: 0.5,
      className: 'robot' });
    this.heading = L.polyline([], { color: '#0d1117', weight: 3, className: 'robot-heading' });
  }

  get size(): { width: number; height: number } { return { width: this.info.width, height: this.info.height }; }

  // Shows a new revision of the map (after an edit or a change of map).
  setMap(info: MapInfo): void {
    this.info = info;
    this.image.setUrl(info.image_url);
    this.image.setBounds(this.bounds(info));
    this.traffic.setBounds(this.bounds(info));
  }

  // Fetches the traffic overlay again, at most every two seconds (the tracker hands the planner new costs every
  // second), while there is any (`present`, from the state); hides it when there is none.
  showTraffic(present: boolean): void {
    if (!present) {
      if (this.trafficAt !== 0) this.traffic.setOpacity(0).setUrl(kNoImage);
      this.trafficAt = 0;
      return;
    }
    const now = Date.now();
    if (now - this.trafficAt < 2000) return;
    this.trafficAt = now;
    this.traffic.setUrl(`/api/v1/map/traffic?t=${now}`);
  }

  // `element` as a control over the map at `position` (its clicks and drags are the element's, not the map's).
  addControl(element: HTMLElement, position: L.ControlPosition): void {
    const control = new L.Control({ position });
    control.onAdd = () => {
      L.DomEvent.disableClickPropagation(element);
      L.DomEvent.disableScrollPropagation(element);
      return element;
    };
    control.addTo(this.map);
  }

  // Pans the map to `pose`, keeping the zoom.
  centreOn(pose: Pose): void {
    this.map.panTo(toLatLng(pose.x, pose.y));
  }

  // The laser's scan: its points (metres, map frame) as small dots; none clears it.
  showScan(points: [number, number][]): void {
    this.scan.clearLayers();
    for (const [x, y] of points) {
      L.circleMarker(toLatLng(x, y), { renderer: this.scanRenderer, radius: 1.5, weight: 0, fillColor: '#e3b341',
        fillOpacity: 1, interactive: false }).addTo(this.scan);
    }
  }

  // The map cell under a map-frame point, or null outside the map.
  cellAt(x: number, y: number): { col: number; row: number } | null {
    const col = Math.floor((x - this.info.origin.x) / this.info.resolution_m);
    const row = Math.floor((y - this.info.origin.y) / this.info.resolution_m);
    if (col < 0 || row < 0 || col >= this.info.width || row >= this.info.height) return null;
    return { col, row };
  }

  // The simulator's people (moving) and unmapped obstacles (redrawn only when they change).
  showSimulation(people: SimPerson[], obstacles: SimObstacle[]): void {
    this.simPeople.clearLayers();
    for (const p of people) {
      L.circle(toLatLng(p.x, p.y), { radius: p.radius_m, color: '#8250df', weight: 1, fillOpacity: 0.6,
        className: 'sim-person' }).addTo(this.simPeople);
      L.polyline([toLatLng(p.x, p.y), toLatLng(p.x + p.vx, p.y + p.vy)], { color: '#8250df', weight: 2 })
        .addTo(this.simPeople);
    }
    const key = JSON.stringify(obstacles);
    if (key === this.shownObstacles) return;
    this.shownObstacles = key;
    this.simObstacles.clearLayers();
    const style = { color: '#bc4c00', weight: 1, fillOpacity: 0.5, className: 'sim-obstacle' };
    for (const o of obstacles) {
      if (o.shape === 'cylinder') {
        L.circle(toLatLng(o.x, o.y), { radius: o.size_m, ...style }).addTo(this.simObstacles);
        continue;
      }
      const corners = [[1, 1], [-1, 1], [-1, -1], [1, -1]].map(([cx, cy]) => {
        const lx = cx * o.size_m;
        const ly = cy * o.size_m;
        return toLatLng(o.x + lx * Math.cos(o.yaw) - ly * Math.sin(o.yaw), o.y + lx * Math.sin(o.yaw) + ly * Math.cos(o.yaw));
      });
      L.polygon(corners, style).addTo(this.simObstacles);
    }
  }

  // What the tracker follows: moving objects as dashed rings with their velocity over the next second (paler while
  // not seen), standing ones as small grey rings.
  showTracked(objects: TrackedObject[]): void {
    this.tracked.clearLayers();
    for (const o of objects) {
      const radius = Math.max(o.radius_m, 0.1);
      if (!o.moving) {
        L.circle(toLatLng(o.x, o.y), { radius, color: '#6e7781', weight: 1, fill: false, className: 'tracked-still' })
          .addTo(this.tracked);
        continue;
      }
      // Not seen (out of the camera's view, or hidden): where they are expected, paler.
      const opacity = o.seen ? 1 : 0.4;
      L.circle(toLatLng(o.x, o.y), { radius, color: '#cf222e', weight: 2, dashArray: '4 3', fill: false, opacity,
        className: o.seen ? 'tracked-moving' : 'tracked-moving tracked-unseen' }).addTo(this.tracked);
      L.polyline([toLatLng(o.x, o.y), toLatLng(o.x + o.vx, o.y + o.vy)], { color: '#cf222e', weight: 2, opacity })
        .addTo(this.tracked);
      // Where they are expected to turn round: a dotted line to the end of their walk.
      if (o.walk_end) {
        L.polyline([toLatLng(o.x, o.y), toLatLng(o.walk_end.x, o.walk_end.y)], { color: '#cf222e', weight: 1,
          dashArray: '1 4', className: 'tracked-walk-end' }).addTo(this.tracked);
      }
    }
  }

  showRobot(pose: Pose | null, truth: Pose | null): void {
    if (pose) {
      const at = toLatLng(pose.x, pose.y);
      const tip = toLatLng(pose.x + 2 * this.footprintRadius * Math.cos(pose.yaw),
        pose.y + 2 * this.footprintRadius * Math.sin(pose.yaw));
      this.footprint.setLatLng(at).addTo(this.map);
      this.heading.setLatLngs([at, tip]).addTo(this.map);
      const points = this.trail.getLatLngs() as L.LatLng[];
      const last = points[points.length - 1];
      if (!last || last.distanceTo(at) > 0.05) {
        points.push(at);
        if (points.length > kTrailLength) points.shift();
        this.trail.setLatLngs(points);
      }
      if (!this.followed) {
        this.map.setView(at, 5, { animate: false });  // 32 px per metre: the robot and the rooms around it
        this.followed = true;
      }
    }
    if (truth) this.ghost.setLatLng(toLatLng(truth.x, truth.y)).addTo(this.map);
  }

  // MORP's dead-ends (base-frame points) placed on the map through the robot's pose.
  showDeadEnds(points: [number, number][], pose: Pose | null): void {
    this.deadEnds.clearLayers();
    if (!pose) return;
    const c = Math.cos(pose.yaw);
    const s = Math.sin(pose.yaw);
    for (const [x, y] of points) {
      L.circleMarker(toLatLng(pose.x + c * x - s * y, pose.y + s * x + c * y),
        { radius: 3, color: '#f85149', fillOpacity: 1, className: 'dead-end' }).addTo(this.deadEnds);
    }
  }

  // The people detected in the camera (positions in the base frame at `pose`), each with its track id.
  showPeople(people: Detection[], pose: Pose | null): void {
    this.people.clearLayers();
    if (!pose) return;
    const c = Math.cos(pose.yaw);
    const s = Math.sin(pose.yaw);
    for (const p of people) {
      if (!p.position) continue;
      const { x, y } = p.position;
      L.circleMarker(toLatLng(pose.x + c * x - s * y, pose.y + s * x + c * y),
        { radius: 7, color: '#8250df', weight: 2, fillOpacity: 0.3, className: 'detected-person' })
        .bindTooltip(`${p.class} ${p.track_id} (${p.source}, ${Math.round(p.score * 100)} %)`)
        .addTo(this.people);
    }
  }

  showMission(mission: Mission | null): void {
    const live = mission && (mission.status === 'active' || mission.status === 'paused');
    this.missionPath.setLatLngs(live ? mission.path.map((p) => toLatLng(p.x, p.y)) : []);
    this.missionGoals.clearLayers();
    if (!live) return;
    mission.waypoints.forEach((w, i) => {
      L.circleMarker(toLatLng(w.x, w.y), { radius: 5, color: i < mission.current_waypoint ? '#888' : '#2ea043',
        className: 'mission-waypoint' }).addTo(this.missionGoals);
    });
  }

  // A fleet manager's order: the last node traversed (grey) and those still to traverse as squares, and the edges
  // between them, the base (released) solid and the horizon dashed and hollow (redrawn only when it changes).
  showFleetOrder(order: FleetOrder | null): void {
    const key = JSON.stringify(order ? [order.nodes, order.edges] : null);
    if (key === this.shownFleetOrder) return;
    this.shownFleetOrder = key;
    this.fleetOrder.clearLayers();
    if (!order) return;
    const at = new Map(order.nodes.map((n) => [n.id, toLatLng(n.x, n.y)]));
    for (const e of order.edges) {
      const from = at.get(e.start);
      const to = at.get(e.end);
      if (!from || !to) continue;
      L.polyline([from, to], { color: '#bf8700', weight: 3, opacity: 0.9, dashArray: e.released ? undefined : '6 6',
        className: e.released ? 'fleet-edge' : 'fleet-edge fleet-horizon' }).addTo(this.fleetOrder);
    }
    for (const n of order.nodes) {
      const half = 0.12;
      L.rectangle(L.latLngBounds(toLatLng(n.x - half, n.y - half), toLatLng(n.x + half, n.y + half)), {
        color: n.traversed ? '#888' : '#bf8700', weight: 2, fill: n.released, fillOpacity: 0.8,
        className: `fleet-node${n.traversed ? ' fleet-traversed' : n.released ? '' : ' fleet-horizon'}`,
      }).bindTooltip(n.id).addTo(this.fleetOrder);
    }
  }

  private bounds(info: MapInfo): L.LatLngBounds {
    const { x, y } = info.origin;
    return L.latLngBounds(toLatLng(x, y), toLatLng(x + info.width * info.resolution_m, y + info.height * info.resolution_m));
  }
}
