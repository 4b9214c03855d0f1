// The admin page at /admin: users, API tokens, webhooks, the devices plugged in, and the audit log. For admins; anyone else is sent to the
// console (which logs them in).
import { request, send, type LaserScanReading, type State, type Twist } from './api';
import { byId } from './dom';
import { repeat } from './poll';
import { type Me, requireAdmin } from './session';

interface User { username: string; role: string; created: string; }
interface Token { id: string; name: string; role: string; created: string; created_by: string; last_used: string | null; token?: string; }
interface Webhook { id: string; url: string; events: string[]; description: string; }
interface Delivery { status: string; event: string; response_status: number | null; }
interface Hardware {
  serial: { path: string; names: string[]; usb_id: string; driver: string }[];
  video: { path: string; name: string; formats: string[]; driver: string }[];
  openni2: { uri: string; name: string; vendor: string }[];
}
interface CameraCalibration {
  height_m: number; tilt_deg: number; roll_deg: number; inlier_fraction: number;
  configured: { height_m: number; tilt_deg: number }; patch: object;
}
interface LaserCalibration { yaw_deg: number; configured: { yaw_deg: number }; score: number; points: number; patch: object; }
interface WheelRun {
  run: 'straight' | 'turn'; unit: string; odometry: number; measured: number; score: number;
  diameter_factor: number; track_factor: number; patch: object | null;
}
interface AuditRecord {
  sequence: number; time: string; who: string; client: string; method: string; path: string; status: number;
  detail: string;
}

// What webhooks can be told (GET /api/v1/events' kinds), for the form's checkboxes.
const kEventTypes = ['mission_succeeded', 'mission_failed', 'blocked', 'waiting', 'lost', 'fault', 'bump',
  'battery_low', 'person_detected', 'person_left'];
const kAuditPage = 50;

function report(e: Error): void {
  byId('admin-message').textContent = e.message;
}

// A table row of text cells, and optionally a button at its end.
function row(cells: string[], button?: { label: string; testId: string; onClick: () => void }): HTMLTableRowElement {
  const tr = document.createElement('tr');
  for (const text of cells) {
    const td = document.createElement('td');
    td.textContent = text;
    tr.append(td);
  }
  const td = document.createElement('td');
  if (button) {
    const b = document.createElement('button');
    b.textContent = button.label;
    b.dataset.testid = button.testId;
    b.addEventListener('click', button.onClick);
    td.append(b);
  }
  tr.append(td);
  return tr;
}

const day = (iso: string | null) => (iso ? iso.replace('T', ' ').slice(0, 16) : 'never');

async function showUsers(me: Me): Promise<void> {
  const { users } = await send<{ users: User[] }>('GET', '/api/v1/users');
  byId('users').replaceChildren(...users.map((u) => row([u.username, u.role, day(u.created)],
    u.username === me.name ? undefined : {
      label: 'Delete', testId: `delete-user-${u.username}`,
      onClick: () => void send('DELETE', `/api/v1/users/${encodeURIComponent(u.username)}`)
        .then(() => refresh(me)).catch(report),
    })));
}

async function showTokens(me: Me): Promise<void> {
  const { tokens } = await send<{ tokens: Token[] }>('GET', '/api/v1/tokens');
  byId('tokens').replaceChildren(...tokens.map((t) => row([t.name, t.role, day(t.created), t.created_by, day(t.last_used)], {
    label: 'Revoke', testId: `revoke-${t.name}`,
    onClick: () => void send('DELETE', `/api/v1/tokens/${t.id}`).then(() => refresh(me)).catch(report),
  })));
}

async function showWebhooks(me: Me): Promise<void> {
  const { webhooks } = await send<{ webhooks: Webhook[] }>('GET', '/api/v1/webhooks');
  const rows = await Promise.all(webhooks.map(async (w) => {
    const { deliveries } = await send<{ deliveries: Delivery[] }>('GET', `/api/v1/webhooks/${w.id}/deliveries`);
    const recent = deliveries.slice(0, 3).map((d) => `${d.event} ${d.status}${d.response_status ? ` (${d.response_status})` : ''}`);
    const tr = row([w.url, w.events.join(', '), recent.join('; ') || 'none'], {
      label: 'Delete', testId: `delete-webhook-${w.id}`,
      onClick: () => void send('DELETE', `/api/v1/webhooks/${w.id}`).then(() => refresh(me)).catch(report),
    });
    // A test delivery now (a ping): its outcome shows among the last deliveries.
    const test = document.createElement('button');
    test.textContent = 'Test';
    test.dataset.testid = `test-webhook-${w.id}`;
    test.addEventListener('click', () => void send('POST', `/api/v1/webhooks/${w.id}/ping`)
      .then(() => new Promise((r) => window.setTimeout(r, 1000))).then(() => showWebhooks(me)).catch(report));
    tr.lastElementChild?.prepend(test, ' ');
    return tr;
  }));
  byId('webhooks').replaceChildren(...rows);
}

// The audit log by pages of kAuditPage, newest first, with the form's filters: `before` pages back (0: the newest).
const audit = { before: 0, pages: [] as number[] };
async function showAudit(): Promise<void> {
  const params = new URLSearchParams({ limit: String(kAuditPage) });
  if (audit.before > 0) params.set('before', String(audit.before));
  const who = byId<HTMLInputElement>('audit-who').value.trim();
  const path = byId<HTMLInputElement>('audit-path').value.trim();
  if (who) params.set('who', who);
  if (path) params.set('path', path);
  if (byId<HTMLInputElement>('audit-failed').checked) params.set('failed', 'true');
  const { records } = await send<{ records: AuditRecord[] }>('GET', `/api/v1/audit?${params}`);
  byId('audit').replaceChildren(...records.slice().reverse().map((r) =>
    row([day(r.time), r.who, r.client, `${r.method} ${r.path}`, String(r.status), r.detail])));
  const older = byId<HTMLButtonElement>('audit-older');
  older.disabled = records.length < kAuditPage;
  older.onclick = () => {
    audit.pages.push(audit.before);
    audit.before = records[0].sequence;
    void showAudit().catch(report);
  };
  const newer = byId<HTMLButtonElement>('audit-newer');
  newer.disabled = audit.pages.length === 0;
  newer.onclick = () => {
    audit.before = audit.pages.pop() ?? 0;
    void showAudit().catch(report);
  };
  byId('audit-page').textContent = records.length === 0 ? 'none'
    : `${records.length} record(s)${audit.pages.length > 0 ? `, page ${audit.pages.length + 1}` : ''}`;
}

// Serial ports (by their stable names and USB ids), video nodes and OpenNI2 devices, each with the driver it suggests.
async function showHardware(): Promise<void> {
  const h = await send<Hardware>('GET', '/api/v1/devices/hardware');
  const rows = [
    ...h.serial.map((p) => row(['serial', p.path, p.names.join(' '), p.usb_id ? `USB ${p.usb_id}` : '', p.driver || '—'])),
    ...h.video.map((v) => row(['video', v.path, '', `${v.name} (${v.formats.join(', ')})`, v.driver || '—'])),
    ...h.openni2.map((d) => row(['OpenNI2', d.uri, '', `${d.vendor} ${d.name}`, 'openni2'])),
  ];
  byId('hardware').replaceChildren(...(rows.length > 0 ? rows : [row(['nothing plugged in', '', '', '', ''])]));
}

// A calibration's section on the page: the returned function runs a measurement (`measure` answers what to show and
// the configuration patch that keeps it, or none) and shows it; Keep it writes the last patch (PATCH /api/v1/config,
// read at the next start).
type Measure = () => Promise<{ text: string; patch: object | null }>;
function calibration(name: string): (measure: Measure) => void {
  const out = byId(`${name}-calibration`);
  const keep = byId<HTMLButtonElement>(`${name}-keep`);
  let patch: object | null = null;
  keep.addEventListener('click', () => {
    if (!patch) return;
    send<{ detail: string }>('PATCH', '/api/v1/config', patch).then((result) => {
      out.textContent = `kept: ${result.detail}`;
      keep.hidden = true;
    }).catch(report);
  });
  return (measure) => {
    patch = null;
    keep.hidden = true;
    out.textContent = 'measuring…';
    measure().then((m) => {
      out.textContent = m.text;
      patch = m.patch;
      keep.hidden = patch === null;
    }).catch((e: Error) => { out.textContent = e.message; });
  };
}

// The camera's height and tilt from the floor, beside the configured ones.
async function measureCamera(): Promise<{ text: string; patch: object }> {
  const c = await send<CameraCalibration>('POST', '/api/v1/devices/camera/calibration', {});
  return {
    text: `height ${c.height_m.toFixed(3)} m (configured ${c.configured.height_m.toFixed(3)}), `
      + `tilt ${c.tilt_deg.toFixed(1)}° (configured ${c.configured.tilt_deg.toFixed(1)}), roll ${c.roll_deg.toFixed(1)}°, `
      + `${(100 * c.inlier_fraction).toFixed(0)} % of the image's lower half on the floor`,
    patch: c.patch,
  };
}

// The laser's yaw laid on the camera's view.
async function measureLaser(): Promise<{ text: string; patch: object }> {
  const c = await send<LaserCalibration>('POST', '/api/v1/devices/laser/calibration', {});
  return {
    text: `yaw ${c.yaw_deg.toFixed(1)}° (configured ${c.configured.yaw_deg.toFixed(1)}), ${c.points} points matched, `
      + `score ${c.score.toFixed(2)}`,
    patch: c.patch,
  };
}

// The wheels: a run started where the robot stands; finished after a straight run or a turn on the spot.
async function startWheelRun(): Promise<{ text: string; patch: null }> {
  const started = await send<{ next: string }>('POST', '/api/v1/devices/wheels/calibration/start', {});
  return { text: `started: ${started.next}`, patch: null };
}

async function finishWheelRun(): Promise<{ text: string; patch: object | null }> {
  const w = await send<WheelRun>('POST', '/api/v1/devices/wheels/calibration/finish', {});
  const factor = w.run === 'straight'
    ? `wheel diameter × ${w.diameter_factor.toFixed(4)}`
    : `track × ${w.track_factor.toFixed(4)} (wheel diameter × ${w.diameter_factor.toFixed(4)})`;
  return {
    text: `${w.run}: ${w.measured.toFixed(w.unit === 'm' ? 3 : 1)} ${w.unit} measured, `
      + `${w.odometry.toFixed(w.unit === 'm' ? 3 : 1)} ${w.unit} by odometry: ${factor}`
      + (w.patch ? '' : ' (this base\'s odometry is its ROS 2 driver\'s: set its wheels there)'),
    patch: w.patch,
  };
}

// The devices as the robot runs them, while the live view is open: each slot's driver and health, the laser's scan
// (robot at the centre, forward up), the depth camera's frame, the base's motion and battery.
const kLivePeriodMs = 500;
let depthUrl: string | null = null;
async function showLive(): Promise<void> {
  const state = await send<State>('GET', '/api/v1/state');
  byId('slots').replaceChildren(...state.devices.map((d) => row([
    d.device, d.driver, d.port || '—', d.link ? `${d.state} (${d.link})` : d.state, `${d.rate_hz.toFixed(1)} Hz`,
    d.last_error ?? ''])));
  const battery = state.battery
    ? `battery ${state.battery.percent.toFixed(0)} % (${state.battery.voltage_v.toFixed(1)} V${state.battery.charging ? ', charging' : ''})`
    : 'no battery reported';
  byId('live-base').textContent = `base: ${state.velocity.linear_mps.toFixed(2)} m/s, `
    + `${state.velocity.angular_rps.toFixed(2)} rad/s${state.bumper_pressed ? ', bumper pressed' : ''}; ${battery}`;
  const has = (device: string) => state.devices.some((d) => d.device === device);
  if (has('laser')) drawScan(await send<LaserScanReading>('GET', '/api/v1/laser/scan'));
  if (has('camera')) {
    const res = await request('/api/v1/camera/depth?colormap=true', { cache: 'no-store' });
    if (res.ok) {
      const next = URL.createObjectURL(await res.blob());
      byId<HTMLImageElement>('live-depth').src = next;
      if (depthUrl) URL.revokeObjectURL(depthUrl);
      depthUrl = next;
    }
  }
}

function drawScan(scan: LaserScanReading): void {
  const canvas = byId<HTMLCanvasElement>('live-scan');
  const ctx = canvas.getContext('2d');
  if (!ctx) return;
  const scale = canvas.width / 2 / Math.min(scan.range_max_m, 6);  // pixels a metre: 6 m to the edge at most
  const cx = canvas.width / 2;
  const cy = canvas.height / 2;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.strokeStyle = '#2b313b';
  for (let r = 1; r * scale < canvas.width / 2; ++r) {
    ctx.beginPath();
    ctx.arc(cx, cy, r * scale, 0, 2 * Math.PI);
    ctx.stroke();
  }
  ctx.fillStyle = '#f85149';
  const mount = scan.base_T_laser;
  scan.ranges.forEach((range, i) => {
    if (range === null) return;
    const a = scan.angle_min_rad + i * scan.angle_increment_rad + mount.yaw;
    const x = mount.x + range * Math.cos(a);  // base frame: x forward (up on the canvas), y left
    const y = mount.y + range * Math.sin(a);
    ctx.fillRect(cx - y * scale - 1, cy - x * scale - 1, 2, 2);
  });
  ctx.fillStyle = '#58a6ff';
  ctx.fillRect(cx - 3, cy - 3, 6, 6);
}

// A short move through the teleop path: the command repeated (a command lapses after half a second) for 1 s, then
// zero. Moves 10 cm or turns 15 degrees where nothing stops it.
const kJogs: Record<string, Twist> = {
  forward: { linear_mps: 0.1, angular_rps: 0 },
  back: { linear_mps: -0.1, angular_rps: 0 },
  left: { linear_mps: 0, angular_rps: Math.PI / 12 },
  right: { linear_mps: 0, angular_rps: -Math.PI / 12 },
};
async function jog(direction: string): Promise<void> {
  const twist = kJogs[direction];
  const end = Date.now() + 1000;
  while (Date.now() < end) {
    await send('POST', '/api/v1/teleop', twist);
    await new Promise((resolve) => window.setTimeout(resolve, 100));
  }
  await send('POST', '/api/v1/teleop', { linear_mps: 0, angular_rps: 0 });
}

function refresh(me: Me): Promise<void> {
  return Promise.all([showUsers(me), showTokens(me), showWebhooks(me), showHardware(), showAudit()]).then(() => undefined);
}

async function main(): Promise<void> {
  const me = await requireAdmin();
  if (!me) return;
  byId('user-form').addEventListener('submit', (event) => {
    event.preventDefault();
    const body = {
      username: byId<HTMLInputElement>('user-name').value,
      password: byId<HTMLInputElement>('user-password').value,
      role: byId<HTMLSelectElement>('user-role').value,
    };
    send('POST', '/api/v1/users', body).then(() => {
      byId<HTMLFormElement>('user-form').reset();
      return refresh(me);
    }).catch(report);
  });
  byId('token-form').addEventListener('submit', (event) => {
    event.preventDefault();
    const body = { name: byId<HTMLInputElement>('token-name').value, role: byId<HTMLSelectElement>('token-role').value };
    send<Token>('POST', '/api/v1/tokens', body).then((made) => {
      const secret = byId('token-secret');
      secret.hidden = false;
      secret.textContent = `${made.name}: ${made.token ?? ''} (copy it now: it is not shown again)`;
      return refresh(me);
    }).catch(report);
  });
  byId('audit-refresh').addEventListener('click', () => void showAudit().catch(report));
  byId('audit-filter').addEventListener('submit', (event) => {
    event.preventDefault();
    audit.before = 0;
    audit.pages = [];
    void showAudit().catch(report);
  });
  const events = byId('webhook-events');
  for (const type of kEventTypes) {
    const label = document.createElement('label');
    const box = document.createElement('input');
    box.type = 'checkbox';
    box.value = type;
    box.defaultChecked = !type.startsWith('person_');
    label.append(box, ` ${type.replaceAll('_', ' ')}`);
    events.append(label);
  }
  byId('webhook-form').addEventListener('submit', (event) => {
    event.preventDefault();
    const chosen = [...events.querySelectorAll<HTMLInputElement>('input:checked')].map((b) => b.value);
    const description = byId<HTMLInputElement>('webhook-description').value.trim();
    const body = { url: byId<HTMLInputElement>('webhook-url').value.trim(), events: chosen,
      ...(description ? { description } : {}) };
    send<Webhook & { secret: string }>('POST', '/api/v1/webhooks', body).then((made) => {
      const secret = byId('webhook-secret');
      secret.hidden = false;
      secret.textContent = `${made.url}: signing secret ${made.secret} (copy it now: it is not shown again)`;
      byId<HTMLFormElement>('webhook-form').reset();
      return refresh(me);
    }).catch(report);
  });
  byId('hardware-refresh').addEventListener('click', () => void showHardware().catch(report));
  const camera = calibration('camera');
  const laser = calibration('laser');
  const wheels = calibration('wheels');
  byId('camera-measure').addEventListener('click', () => camera(measureCamera));
  byId('laser-measure').addEventListener('click', () => laser(measureLaser));
  byId('wheels-start').addEventListener('click', () => wheels(startWheelRun));
  byId('wheels-finish').addEventListener('click', () => wheels(finishWheelRun));
  for (const button of document.querySelectorAll<HTMLButtonElement>('[data-jog]')) {
    button.addEventListener('click', () => void jog(button.dataset.jog ?? '').catch(report));
  }
  const live = byId<HTMLDetailsElement>('live');
  repeat(async () => { if (live.open) await showLive(); }, kLivePeriodMs, report);
  await refresh(me).catch(report);
}

void main();
