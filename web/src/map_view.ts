// The map with pan and zoom (Leaflet, in metres: CRS.Simple with lat = y and lng = x of the map frame), the robot
// as its footprint and heading, its recent trail, and the simulator's ground truth as a faint ghost.
import L from 'leaflet';

import type { MapInfo, Pose } from './api';

const kTrailLength = 600;

export class MapView {
  private readonly map: L.Map;
  private readonly footprint: L.Circle;
  private readonly heading: L.Polyline;
  private readonly ghost: L.Circle;
  private readonly trail: L.Polyline;
  private followed = false;

  constructor(element: HTMLElement, info: MapInfo, private readonly footprintRadius: number) {
    this.map = L.map(element, { crs: L.CRS.Simple, minZoom: -3, maxZoom: 6, zoomSnap: 0.25, attributionControl: false });
    const { x, y } = info.origin;
    const bounds = L.latLngBounds([y, x], [y + info.height * info.resolution_m, x + info.width * info.resolution_m]);
    L.imageOverlay(info.image_url, bounds, { className: 'map-image' }).addTo(this.map);
    this.map.fitBounds(bounds);
    this.trail = L.polyline([], { color: '#58a6ff', weight: 2, opacity: 0.6, className: 'robot-trail' }).addTo(this.map);
    this.ghost = L.circle([0, 0], { radius: footprintRadius, color: '#888', weight: 1, fill: false, dashArray: '3',
      className: 'robot-truth' });
    this.footprint = L.circle([0, 0], { radius: footprintRadius, color: '#1f6feb', weight: 2, fillOpacity: 0.5,
      className: 'robot' });
    this.heading = L.polyline([], { color: '#0d1117', weight: 3, className: 'robot-heading' });
  }

  showRobot(pose: Pose | null, truth: Pose | null): void {
    if (pose) {
      const at = L.latLng(pose.y, pose.x);
      const tip = L.latLng(pose.y + 2 * this.footprintRadius * Math.sin(pose.yaw),
        pose.x + 2 * this.footprintRadius * Math.cos(pose.yaw));
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
        this.map.setView(at, 5);  // 32 px per metre: the robot and the rooms around it
        this.followed = true;
      }
    }
    if (truth) this.ghost.setLatLng([truth.y, truth.x]).addTo(this.map);
  }
}
