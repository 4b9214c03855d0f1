// The corridor console: map, live pose, camera, telemetry, teleoperation, and the navigation tools.
import {
  request, send, type Detections, type Device, type GroundLanes, type LaserScanReading, type MapInfo, type Mission,
  type Pose, type State, type Twist,
} from './api';
import { byId, type Report } from './dom';
import { EventsPanel } from './events';
import { FacePanel } from './face_panel';
import { Plots } from './plots';
import { setUpLayout, shown } from './layout';
import { repeat } from './poll';
import { LocalizationPanel } from './localization';
import { MapView } from './map_view';
import { MapsPanel } from './maps';
import { MappingPanel } from './mapping';
import { OctomapView } from './octomap_view';
import { BuildingLayers } from './building';
import { applyRole, mayDo, permitted, requireSession } from './session';
import { Stream } from './stream';
import { Teleop } from './teleop';
import { Tools } from './tools';
import { ZoneLayers } from './zones';

const kCameraPeriodMs = 200;
const kScanPeriodMs = 500;
// The console drives at a walking pace; the daemon clamps to its own limits anyway.
const kTeleopLimits = { maxLinear: 0.4, maxAngular: 1.0 };
const kFootprintRadius = 0.2;

function deg(rad: number): string {
  return `${((rad * 180) / Math.PI).toFixed(1)}°`;
}

// The message line under the mission panel: the latest outcome only, an error in red, gone after a while.
let reportTimer = 0;
const report: Report = (message, undo) => {
  const line = byId('message');
  const error = message instanceof Error;
  line.textContent = error ? message.message : message;
  line.className = error ? 'error' : 'muted';
  if (undo) {
    const button = document.createElement('button');
    button.textContent = undo.label;
    button.dataset.testid = 'message-undo';
    button.addEventListener('click', () => {
      line.textContent = '';
      undo.run();
    });
    line.append(' ', button);
  }
  window.clearTimeout(reportTimer);
  reportTimer = window.setTimeout(() => { line.textContent = ''; }, error ? 15000 : undo ? 10000 : 6000);
};

function showMission(mission: Mission | null): void {
  const status = byId('mission-status');
  const live = mission !== null && (mission.status === 'active' || mission.status === 'paused');
  if (!mission) {
    status.textContent = 'none';
  } else {
    const where = mission.waypoints.length > 1 ? ` (waypoint ${mission.current_waypoint + 1} of ${mission.waypoints.length})` : '';
    const docking = live && mission.docking ? `, docking: ${mission.docking}` : '';
    const lift = live && mission.lift ? `, lift: ${mission.lift.replaceAll('_', ' ')}` : '';
    status.textContent =
      `${mission.status}${live ? where : ''}${docking}${lift}${mission.error ? `: ${mission.error}` : ''}`;
  }
  byId<HTMLProgressElement>('mission-progress').value = mission?.progress ?? 0;
  // While it waits (for a door, a lift, a way past what blocks it), the console says what for, not a frozen ETA.
  const waiting = mission?.waiting ?? '';
  const eta = byId('mission-eta');
  eta.textContent = waiting ? `waiting for ${waiting}` : live ? `about ${Math.ceil(mission.eta_s)} s to go` : '';
  eta.classList.toggle('waiting', waiting !== '');
  const enable = (id: string, on: boolean) => {
    const button = byId<HTMLButtonElement>(id);
    button.disabled = !on || !permitted(button);
  };
  enable('mission-pause', mission?.status === 'active');
  enable('mission-resume', mission?.status === 'paused');
  enable('mission-cancel', live);
}

// The battery's charge in the header (red when low) and its detail in the telemetry.
function showBattery(state: State): void {
  const badge = byId('battery');
  const b = state.battery;
  if (!b) {
    badge.textContent = 'no battery';
    byId('battery-detail').textContent = '—';
    return;
  }
  const doing = b.charging ? 'charging' : b.on_charger ? 'on the dock' : '';
  badge.textContent = `${Math.round(b.percent)} %${doing ? ` ${doing}` : ''}`;
  badge.classList.toggle('low', b.percent < 20 && !b.charging);
  byId('battery-detail').textContent =
    `${b.percent.toFixed(1)} %, ${b.voltage_v.toFixed(2)} V, ${b.current_a.toFixed(2)} A${state.docked ? ', docked' : ''}`;
  const undock = byId<HTMLButtonElement>('undock');
  undock.disabled = !state.docked || !permitted(undock);
  const dock = byId<HTMLButtonElement>('dock');
  dock.disabled = state.docked || !permitted(dock);
}

// Each device's health: state (coloured), rate and driver; its port, link and last error on hover.
function showDevices(devices: Device[]): void {
  const health = { ok: 'ok', stale: 'degraded', disconnected: 'error' } as const;
  byId('devices').replaceChildren(...devices.map((d) => {
    const tr = document.createElement('tr');
    tr.dataset.device = d.device;
    tr.title = [d.port, d.link ? `link ${d.link}` : '', d.reconnects > 0 ? `${d.reconnects} reconnects` : '',
      d.last_error ?? ''].filter((t) => t !== '').join(', ');
    for (const [text, cls] of [[d.device, ''], [d.state, `health-${health[d.state]}`],
      [`${d.rate_hz.toFixed(1)} Hz`, ''], [d.driver, '']]) {
      const td = document.createElement('td');
      td.textContent = text;
      if (cls) td.className = cls;
      tr.appendChild(td);
    }
    return tr;
  }));
}

// The fleet manager's connection and order (VDA 5050), when one is configured.
function showFleet(state: State): void {
  const f = state.fleet;
  if (!f) {
    byId('fleet').textContent = '—';
    return;
  }
  const link = f.connected ? 'VDA 5050 connected' : 'VDA 5050 not connected';
  const ahead = f.nodes.filter((n) => !n.traversed);
  const next = ahead.find((n) => n.released);
  const order = f.order_id
    ? `, order ${f.order_id}/${f.order_update_id}${next ? `, next ${next.id}` : ''}` +
      `${ahead.length > 0 && !next ? ', waiting for the order to be extended' : ''}`
    : '';
  byId('fleet').textContent = link + order;
}

function showState(state: State, view: MapView | null): void {
  byId('mode').textContent = state.mode === 'stopped' ? `stopped: ${state.stop_reason}` : state.mode;
  byId('pose').textContent = state.pose
    ? `x ${state.pose.x.toFixed(2)} m, y ${state.pose.y.toFixed(2)} m, ${deg(state.pose.yaw)}` : '—';
  byId('speed').textContent = `${state.velocity.linear_mps.toFixed(2)} m/s, ${deg(state.velocity.angular_rps)}/s`;
  byId('command').textContent = `${state.command.linear_mps.toFixed(2)} m/s, ${deg(state.command.angular_rps)}/s`;
  byId('bumper').textContent = state.bumper_pressed ? 'pressed' : 'free';
  byId('face').textContent = state.face;
  showBattery(state);
  showFleet(state);
  const latency = state.control_latency;
  byId('control-loop').textContent = latency && latency.samples > 0
    ? `${latency.rate_hz.toFixed(1)} Hz, frame to command ${latency.p50_ms.toFixed(2)} ms (p99 ${latency.p99_ms.toFixed(2)} ms)`
    : '—';
  byId('policy').textContent = state.mission?.status === 'active' ? (state.mission.policy ?? '—') : '—';
  const rows = state.nodes.map((n) => {
    const tr = document.createElement('tr');
    tr.title = n.message;
    for (const [text, cls] of [[n.name, ''], [n.health, `health-${n.health}`], [`${n.rate_hz.toFixed(1)} Hz`, ''],
      [`${n.worst_loop_ms.toFixed(2)} ms`, '']]) {
      const td = document.createElement('td');
      td.textContent = text;
      if (cls) td.className = cls;
      tr.appendChild(td);
    }
    return tr;
  });
  byId('nodes').replaceChildren(...rows);
  showDevices(state.devices);
  showMission(state.mission);
  view?.showRobot(state.pose, state.sim_true_pose);
  view?.showSimulation(state.sim_pedestrians, state.sim_obstacles);
  view?.showTracked(state.tracked_objects);
  view?.showTraffic(state.map.traffic);
  view?.showMission(state.mission);
  view?.showFleetOrder(state.fleet);
}

// Refreshes the camera image; a fetched blob replaces the old one only when complete, so there is no flicker.
function startCamera(): void {
  const img = byId<HTMLImageElement>('camera');
  const kind = byId<HTMLSelectElement>('camera-kind');
  const status = byId('camera-status');
  let url: string | null = null;
  repeat(async () => {
    if (!shown(img)) return;  // a phone's closed sheet: no image to fetch
    const path = kind.value === 'depth' ? '/api/v1/camera/depth?colormap=true' : '/api/v1/camera/color';
    const res = await request(path, { cache: 'no-store' });
    if (!res.ok) throw new Error(`HTTP ${res.status}`);
    const next = URL.createObjectURL(await res.blob());
    img.src = next;
    if (url) URL.revokeObjectURL(url);
    url = next;
    status.textContent = `frame ${res.headers.get('X-Frame-Sequence') ?? '?'}`;
  }, kCameraPeriodMs, (e) => { status.textContent = `no image: ${e.message}`; });
}

// An overlay canvas over the camera view, cleared and sized to the shown image, with the scale from image pixels; null
// before the first image.
function cameraOverlay(id: string): { ctx: CanvasRenderingContext2D; sx: number; sy: number } | null {
  const img = byId<HTMLImageElement>('camera');
  const canvas = byId<HTMLCanvasElement>(id);
  canvas.width = img.clientWidth;
  canvas.height = img.clientHeight;
  const ctx = canvas.getContext('2d');
  if (!ctx || img.naturalWidth === 0) return null;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  return { ctx, sx: canvas.width / img.naturalWidth, sy: canvas.height / img.naturalHeight };
}

// Each lane's dead-end over the depth view: a red mark at its pixel with the free distance; blind lanes are grey.
function showLanes(ground: GroundLanes, view: MapView | null, pose: Pose | null): void {
  const overlay = cameraOverlay('lanes-overlay');
  if (!overlay) return;
  const { ctx, sx, sy } = overlay;
  ctx.font = '11px system-ui';
  for (const lane of ground.lanes) {
    if (!lane.pixel) continue;
    const [u, v] = lane.pixel;
    ctx.strokeStyle = '#fff';
    ctx.fillStyle = '#f85149';
    ctx.beginPath();
    ctx.arc(u * sx, v * sy, 4, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
    ctx.fillStyle = '#fff';
    ctx.fillText(`${lane.free_distance_m.toFixed(1)}`, u * sx + 5, v * sy - 5);
  }
  const nearest = Math.min(...ground.lanes.map((l) => (l.dead_end ? l.free_distance_m : Infinity)));
  byId('lanes').textContent = `${ground.lanes.length} lanes, nearest dead-end ` +
    `${Number.isFinite(nearest) ? `${nearest.toFixed(2)} m` : 'none'}, ready ${ground.latency_ms.toFixed(2)} ms after the frame` +
    (ground.lanes.some((l) => l.blind) ? ' (blind)' : '');
  view?.showDeadEnds(ground.lanes.filter((l) => l.point).map((l) => [l.point![0], l.point![1]]), pose);
}

// The people and objects detected, as boxes over the camera view (the depth image is registered to the colour one, so
// the boxes fit both) and as people on the map.
function showDetections(detections: Detections, view: MapView | null, pose: Pose | null): void {
  const people = detections.detections.filter((d) => d.class === 'person');
  view?.showPeople(people, pose);
  byId('detections').textContent = detections.detections.length === 0 ? 'nobody'
    : detections.detections.map((d) => `${d.class} ${d.track_id}` +
      (d.position ? ` at ${Math.hypot(d.position.x, d.position.y).toFixed(1)} m` : '')).join(', ');
  const overlay = cameraOverlay('detections-overlay');
  if (!overlay) return;
  const { ctx, sx, sy } = overlay;
  ctx.font = '11px system-ui';
  ctx.lineWidth = 2;
  for (const d of detections.detections) {
    if (!d.box) continue;
    ctx.strokeStyle = d.class === 'person' ? '#a371f7' : '#d29922';
    ctx.strokeRect(d.box.x * sx, d.box.y * sy, d.box.w * sx, d.box.h * sy);
    ctx.fillStyle = ctx.strokeStyle;
    ctx.fillText(`${d.class} ${d.track_id} ${Math.round(d.score * 100)}%`, d.box.x * sx + 2, d.box.y * sy - 3);
  }
}

// The laser's latest scan on the map, through the robot's pose, while the laser is ok (`laserOk`).
function startScan(view: MapView, current: () => { pose: Pose | null; laserOk: boolean }): void {
  repeat(async () => {
    const { pose, laserOk } = current();
    if (!laserOk || !pose) {
      view.showScan([]);
      return;
    }
    const scan = await send<LaserScanReading>('GET', '/api/v1/laser/scan');
    const mount = scan.base_T_laser;
    const points: [number, number][] = [];
    scan.ranges.forEach((r, i) => {
      if (r === null) return;
      const a = scan.angle_min_rad + i * scan.angle_increment_rad;
      const bx = mount.x + r * Math.cos(mount.yaw + a);
      const by = mount.y + r * Math.sin(mount.yaw + a);
      points.push([pose.x + bx * Math.cos(pose.yaw) - by * Math.sin(pose.yaw),
        pose.y + bx * Math.sin(pose.yaw) + by * Math.cos(pose.yaw)]);
    });
    view.showScan(points);
  }, kScanPeriodMs, () => view.showScan([]));
}

// The emergency stop: the robot stopped and its mission paused (POST /api/v1/stop), whatever else is going on.
async function emergencyStop(): Promise<void> {
  try {
    const { paused } = await send<{ paused: Mission | null }>('POST', '/api/v1/stop');
    report(paused ? `stopped; mission paused (resume or cancel it)` : 'stopped');
  } catch (e) {
    report(e as Error);
  }
}

function missionAction(action: 'pause' | 'resume' | 'cancel', current: () => Mission | null): void {
  byId(`mission-${action}`).addEventListener('click', () => {
    const mission = current();
    if (mission) void send('POST', `/api/v1/missions/${mission.id}/${action}`).catch((e: Error) => report(e));
  });
}

async function main(): Promise<void> {
  setUpLayout();
  const me = await requireSession();
  applyRole(me);
  byId('estop').addEventListener('click', () => void emergencyStop());
  const face = new FacePanel(report);
  const plots = new Plots(byId('plots'));
  const maps = new MapsPanel(me, report);
  void maps.reload().catch((e: Error) => report(e));
  void new EventsPanel().start().catch((e: Error) => report(e));
  let view: MapView | null = null;
  let tools: Tools | null = null;
  let building: BuildingLayers | null = null;
  let mission: Mission | null = null;
  let zones: ZoneLayers | null = null;
  let mapRevision = -1;
  let mapName = '';
  let pose: Pose | null = null;
  let laserOk = false;
  // The active map again (after an edit, a change of map, or mapping). Another map brings its own zones, places and
  // doors: what was drawn for the one before goes.
  const showActiveMap = () => {
    void send<MapInfo>('GET', '/api/v1/map').then((info) => {
      view?.setMap(info);
      byId('map-name').textContent = info.name;
      byId('map-in-use').textContent = info.name;
      tools?.clearPaintPreview();
      const reloads = [building?.reload()];
      if (info.name !== mapName) reloads.push(zones?.reload(), tools?.reloadPlaces());
      mapName = info.name;
      void Promise.all(reloads).catch((e: Error) => report(e));
    }).catch((e: Error) => report(e));
  };
  const octomap = new OctomapView(byId<HTMLDetailsElement>('octomap-panel'), byId('octomap-view'));
  try {
    const info = await send<MapInfo>('GET', '/api/v1/map');
    byId('map-name').textContent = info.name;
    byId('map-in-use').textContent = info.name;
    view = new MapView(byId('map'), info, kFootprintRadius);
    mapRevision = info.revision;
    mapName = info.name;
    zones = new ZoneLayers(view.map, report);
    tools = new Tools(view, zones, report);
    tools.attachPlaces();
    building = new BuildingLayers(view.map, report);
    await Promise.all([zones.reload(), tools.reloadPlaces(), building.reload()]);
    const mapView = view;
    mapView.addControl(document.querySelector<HTMLElement>('.map-buttons')!, 'topright');
    mapView.addControl(byId('legend'), 'topright');
    byId('centre-robot').addEventListener('click', () => { if (pose) mapView.centreOn(pose); });
    const legendToggle = byId('legend-toggle');
    legendToggle.addEventListener('click', () => {
      const legend = byId('legend');
      legend.hidden = !legend.hidden;
      legendToggle.setAttribute('aria-expanded', String(!legend.hidden));
    });
    startScan(mapView, () => ({ pose, laserOk }));
    const localization = new LocalizationPanel(view, report);
    const mapping = new MappingPanel(view, report, showActiveMap);
    // For tests and debugging from the browser's console.
    (window as unknown as { corridorConsole: object }).corridorConsole =
      { view, tools, zones, localization, mapping, building, plots };
  } catch (e) {
    byId('map').textContent = `map unavailable: ${(e as Error).message}`;
  }
  for (const action of ['pause', 'resume', 'cancel'] as const) missionAction(action, () => mission);
  const connection = byId('connection');
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  let doorsShownAt = 0;
  let streamMapName = mapName;  // the map the stream last named
  const stream = new Stream(`${scheme}://${location.host}/api/v1/stream`, ['state', 'ground/lanes', 'perception/detections'],
    (topic, data) => {
      if (topic === 'ground/lanes') showLanes(data as GroundLanes, view, pose);
      if (topic === 'perception/detections') showDetections(data as Detections, view, pose);
      if (topic !== 'state') return;
      const state = data as State;
      face.show(state.face);
      plots.add(state);
      pose = state.pose;
      laserOk = state.devices.some((d) => d.device === 'laser' && d.state === 'ok');
      mission = state.mission;
      showState(state, view);
      building?.showFloor(state.floor);
      // The doors' states change while a mission passes them: redrawn at most every second.
      if (building && Date.now() - doorsShownAt > 1000) {
        doorsShownAt = Date.now();
        void building.reloadDoors().catch(() => {});
      }
      octomap.showRobot(state.pose);
      // Another map, or this one edited.
      if (view && (state.map.revision !== mapRevision || state.map.name !== streamMapName)) {
        mapRevision = state.map.revision;
        streamMapName = state.map.name;
        maps.showActive(state.map.name);
        showActiveMap();
      }
    },
    (status) => {
      connection.textContent = status === 'up' ? 'connected' : 'reconnecting…';
      connection.className = `connection ${status}`;
    });
  if (mayDo(me, 'operator')) {
    new Teleop(kTeleopLimits, byId('joystick'), (command: Twist) => {
      stream.send({ type: 'teleop', ...command });
    });
  }
  startCamera();
}

void main();
