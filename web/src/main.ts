// The corridor console: map, live pose, camera, telemetry and teleoperation.
import { fetchJson, type MapInfo, type State, type Twist } from './api';
import { MapView } from './map_view';
import { Stream } from './stream';
import { Teleop } from './teleop';

const kCameraPeriodMs = 200;
// The console drives at a walking pace; the daemon clamps to its own limits anyway.
const kTeleopLimits = { maxLinear: 0.4, maxAngular: 1.0 };
const kFootprintRadius = 0.2;

function byId<T extends HTMLElement>(id: string): T {
  const element = document.getElementById(id);
  if (!element) throw new Error(`missing #${id}`);
  return element as T;
}

function deg(rad: number): string {
  return `${((rad * 180) / Math.PI).toFixed(1)}°`;
}

function showState(state: State, view: MapView | null): void {
  byId('mode').textContent = state.mode === 'stopped' ? `stopped: ${state.stop_reason}` : state.mode;
  byId('pose').textContent = state.pose
    ? `x ${state.pose.x.toFixed(2)} m, y ${state.pose.y.toFixed(2)} m, ${deg(state.pose.yaw)}` : '—';
  byId('speed').textContent = `${state.velocity.linear_mps.toFixed(2)} m/s, ${deg(state.velocity.angular_rps)}/s`;
  byId('command').textContent = `${state.command.linear_mps.toFixed(2)} m/s, ${deg(state.command.angular_rps)}/s`;
  byId('bumper').textContent = state.bumper_pressed ? 'pressed' : 'free';
  byId('face').textContent = state.face;
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
  view?.showRobot(state.pose, state.sim_true_pose);
}

// Refreshes the camera image; a fetched blob replaces the old one only when complete, so there is no flicker.
function startCamera(): void {
  const img = byId<HTMLImageElement>('camera');
  const kind = byId<HTMLSelectElement>('camera-kind');
  const status = byId('camera-status');
  let url: string | null = null;
  const tick = async () => {
    const path = kind.value === 'depth' ? '/api/v1/camera/depth?colormap=true' : '/api/v1/camera/color';
    try {
      const res = await fetch(path, { cache: 'no-store' });
      if (!res.ok) throw new Error(`HTTP ${res.status}`);
      const next = URL.createObjectURL(await res.blob());
      img.src = next;
      if (url) URL.revokeObjectURL(url);
      url = next;
      status.textContent = `frame ${res.headers.get('X-Frame-Sequence') ?? '?'}`;
    } catch (e) {
      status.textContent = `no image: ${(e as Error).message}`;
    }
    window.setTimeout(tick, kCameraPeriodMs);
  };
  void tick();
}

async function main(): Promise<void> {
  let view: MapView | null = null;
  try {
    const info = await fetchJson<MapInfo>('/api/v1/map');
    byId('map-name').textContent = info.name;
    view = new MapView(byId('map'), info, kFootprintRadius);
  } catch (e) {
    byId('map').textContent = `map unavailable: ${(e as Error).message}`;
  }
  const connection = byId('connection');
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  const stream = new Stream(`${scheme}://${location.host}/api/v1/stream`,
    (topic, data) => {
      if (topic === 'state') showState(data as State, view);
    },
    (status) => {
      connection.textContent = status === 'up' ? 'connected' : 'reconnecting…';
      connection.className = `connection ${status}`;
    });
  new Teleop(kTeleopLimits, byId('joystick'), (command: Twist) => {
    stream.send({ type: 'teleop', ...command });
  });
  startCamera();
}

void main();
