// The admin page at /admin: users, API tokens, webhooks, the devices plugged in, and the audit log. For admins; anyone else is sent to the
// console (which logs them in).
import { send } from './api';
import { byId } from './dom';
import { type Me, whoAmI } from './session';

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
interface AuditRecord { time: string; who: string; client: string; method: string; path: string; status: number; detail: string; }

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
    return row([w.url, w.events.join(', '), recent.join('; ') || 'none'], {
      label: 'Delete', testId: `delete-webhook-${w.id}`,
      onClick: () => void send('DELETE', `/api/v1/webhooks/${w.id}`).then(() => refresh(me)).catch(report),
    });
  }));
  byId('webhooks').replaceChildren(...rows);
}

async function showAudit(): Promise<void> {
  const { records } = await send<{ records: AuditRecord[] }>('GET', '/api/v1/audit');
  byId('audit').replaceChildren(...records.reverse().map((r) =>
    row([day(r.time), r.who, r.client, `${r.method} ${r.path}`, String(r.status), r.detail])));
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

// The camera's height and tilt measured from the floor, beside the configured ones; Keep it writes them.
let measured: CameraCalibration | null = null;
async function measureCamera(): Promise<void> {
  const out = byId('camera-calibration');
  const keep = byId<HTMLButtonElement>('camera-keep');
  measured = null;
  keep.hidden = true;
  out.textContent = 'measuring…';
  try {
    const c = await send<CameraCalibration>('POST', '/api/v1/devices/camera/calibration', {});
    measured = c;
    out.textContent = `height ${c.height_m.toFixed(3)} m (configured ${c.configured.height_m.toFixed(3)}), `
      + `tilt ${c.tilt_deg.toFixed(1)}° (configured ${c.configured.tilt_deg.toFixed(1)}), roll ${c.roll_deg.toFixed(1)}°, `
      + `${(100 * c.inlier_fraction).toFixed(0)} % of the image's lower half on the floor`;
    keep.hidden = false;
  } catch (e) {
    out.textContent = (e as Error).message;
  }
}

async function keepCamera(): Promise<void> {
  if (!measured) return;
  const result = await send<{ detail: string }>('PATCH', '/api/v1/config', measured.patch);
  byId('camera-calibration').textContent = `kept: ${result.detail}`;
  byId<HTMLButtonElement>('camera-keep').hidden = true;
}

function refresh(me: Me): Promise<void> {
  return Promise.all([showUsers(me), showTokens(me), showWebhooks(me), showHardware(), showAudit()]).then(() => undefined);
}

async function main(): Promise<void> {
  const me = await whoAmI();
  if (!me || me.role !== 'admin') {
    location.href = '/';
    return;
  }
  byId('user').textContent = `${me.name} (${me.role})`;
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
  byId('hardware-refresh').addEventListener('click', () => void showHardware().catch(report));
  byId('camera-measure').addEventListener('click', () => void measureCamera());
  byId('camera-keep').addEventListener('click', () => void keepCamera().catch(report));
  await refresh(me).catch(report);
}

void main();
