// Localization on the map and in the side panel: the filter's particles (up to 200 of them) and its 95 % ellipse
// of position, the health, and a button to search the whole map. The "Set pose" tool itself is in tools.ts.
import L from 'leaflet';

import { send, type Localization } from './api';
import { byId, type Report } from './dom';
import { toLatLng, type MapView } from './map_view';
import { repeat } from './poll';

const kPollMs = 500;
const kChiSquare2d95 = 5.991;  // the 95 % ellipse of a 2D Gaussian: x' S^-1 x = 5.991

// The ellipse's outline, `points` corners, from the (x, y) block of the covariance.
function ellipse(cx: number, cy: number, sxx: number, sxy: number, syy: number, points = 36): L.LatLng[] {
  // Eigen-decomposition of the symmetric 2 x 2 block.
  const mean = (sxx + syy) / 2;
  const spread = Math.sqrt(((sxx - syy) / 2) ** 2 + sxy * sxy);
  const major = Math.sqrt(Math.max(0, mean + spread) * kChiSquare2d95);
  const minor = Math.sqrt(Math.max(0, mean - spread) * kChiSquare2d95);
  const angle = 0.5 * Math.atan2(2 * sxy, sxx - syy);
  const [c, s] = [Math.cos(angle), Math.sin(angle)];
  const outline: L.LatLng[] = [];
  for (let i = 0; i < points; ++i) {
    const t = (2 * Math.PI * i) / points;
    const [a, b] = [major * Math.cos(t), minor * Math.sin(t)];
    outline.push(toLatLng(cx + c * a - s * b, cy + s * a + c * b));
  }
  return outline;
}

export class LocalizationPanel {
  private readonly layer = L.layerGroup();
  private readonly spread: L.Polygon;
  private last: Localization | null = null;

  constructor(view: MapView, private readonly report: Report) {
    this.layer.addTo(view.map);
    this.spread = L.polygon([], { color: '#d29922', weight: 1, fillOpacity: 0.15, className: 'localization-ellipse' })
      .addTo(view.map);
    byId('relocalize').addEventListener('click', () => {
      send('POST', '/api/v1/localization/relocalize')
        .then(() => this.report('searching the whole map for the robot'))
        .catch((e: Error) => this.report(e));
    });
    byId<HTMLInputElement>('show-particles').addEventListener('change', () => this.draw());
    repeat(async () => {
      this.last = await send<Localization>('GET', '/api/v1/localization');
      this.draw();
    }, kPollMs, (e) => {
      const health = byId('localization-health');
      health.textContent = `unavailable: ${e.message}`;
      health.className = 'health-error';
    });
  }

  get latest(): Localization | null { return this.last; }

  private draw(): void {
    const l = this.last;
    if (!l) return;
    const health = byId('localization-health');
    health.textContent = l.source === 'mcl' ? l.health : `${l.source} (no filter)`;
    health.className = `health-${l.health === 'ok' ? 'ok' : l.health === 'uncertain' ? 'degraded' : 'error'}`;
    const agreement = l.agreement === undefined ? '' : `, ${Math.round(l.agreement * 100)} % of the scan on walls`;
    byId('localization-detail').textContent = l.source === 'mcl'
      ? `${l.sensor ?? ''} · ${l.particle_count} particles${agreement}` : '';
    byId<HTMLButtonElement>('relocalize').disabled = l.source !== 'mcl';
    this.layer.clearLayers();
    if (byId<HTMLInputElement>('show-particles').checked) {
      for (const [x, y, yaw] of l.particles) {
        const tip = toLatLng(x + 0.12 * Math.cos(yaw), y + 0.12 * Math.sin(yaw));
        L.polyline([toLatLng(x, y), tip], { color: '#d29922', weight: 1, className: 'particle' }).addTo(this.layer);
      }
    }
    const c = l.covariance;
    if (l.pose && c && l.source === 'mcl') {
      this.spread.setLatLngs(ellipse(l.pose.x, l.pose.y, c[0], c[1], c[4]));
    } else {
      this.spread.setLatLngs([]);
    }
  }
}
