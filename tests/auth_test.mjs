// Who may use the robot, over real HTTP and WebSocket: setup with the one-time code, sessions, tokens, roles, the
// CSRF and Origin checks, the limit on wrong passwords, and the audit log.
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { createServer } from 'node:http';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  authHeaders, getJson, gotoConsole, launchBrowser, mintToken, openApiValidator, postJson, require, sendJson,
  startDaemon, waitFor, writeRoom,
} from './daemon.mjs';

const WebSocket = require('ws');
const api = openApiValidator();
const none = {};
const bearer = (token) => ({ Authorization: `Bearer ${token}` });

// Each write operation of the OpenAPI contract, with sample values for its path's parameters.
function writeOperations() {
  const out = [];
  for (const [path, item] of Object.entries(api.doc.paths)) {
    for (const method of Object.keys(item)) {
      if (method === 'get') continue;
      out.push({ method: method.toUpperCase(), path: path.replace(/\{[^}]+\}/g, 'x'), secured: item[method].security?.length !== 0 });
    }
  }
  return out;
}

// Logs in over HTTP; resolves the session cookie ("corridor_session=...").
async function logIn(url, username, password) {
  const res = await fetch(`${url}/api/v1/session`, {
    method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ username, password }),
  });
  assert.equal(res.status, 200, await res.text());
  const cookie = res.headers.get('set-cookie');
  assert.match(cookie, /HttpOnly/);
  assert.match(cookie, /SameSite=Strict/);
  return cookie.split(';')[0];
}

describe('roles, tokens and sessions', () => {
  let daemon;
  const tokens = {};
  before(async () => {
    daemon = await startDaemon();
    for (const role of ['viewer', 'operator']) tokens[role] = mintToken(daemon.stateDir, role, role);
    for (const role of ['viewer', 'operator', 'admin']) {
      const made = await postJson(`${daemon.url}/api/v1/users`, { username: `${role}1`, password: `${role}-password`, role });
      assert.equal(made.status, 201, JSON.stringify(made.body));
      api.check('User', made.body);
    }
  });
  after(async () => { await daemon?.stop(); });

  test('every write route refuses without credentials (401) and with too small a role (403)', async () => {
    const operations = writeOperations();
    assert.ok(operations.length > 30, `${operations.length} write operations`);
    for (const { method, path, secured } of operations) {
      const anonymous = await sendJson(method, `${daemon.url}${path}`, {}, 'application/json', none);
      if (!secured) {
        assert.notEqual(anonymous.status, 500, `${method} ${path}`);
        continue;
      }
      assert.equal(anonymous.status, 401, `${method} ${path} without credentials: ${JSON.stringify(anonymous.body)}`);
      api.check('Problem', anonymous.body);
      const viewer = await sendJson(method, `${daemon.url}${path}`, {}, 'application/json', bearer(tokens.viewer));
      assert.equal(viewer.status, 403, `${method} ${path} as a viewer: ${JSON.stringify(viewer.body)}`);
    }
    // An operator drives but does not edit the map.
    const drive = await sendJson('POST', `${daemon.url}/api/v1/teleop`, { linear_mps: 0, angular_rps: 0 },
      'application/json', bearer(tokens.operator));
    assert.equal(drive.status, 200);
    const zone = await sendJson('POST', `${daemon.url}/api/v1/zones`, {}, 'application/json', bearer(tokens.operator));
    assert.equal(zone.status, 403);
    assert.match(zone.body.detail, /admin role needed/);
  });

  test('a viewer reads; admin-only reads refuse them', async () => {
    const state = await sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, bearer(tokens.viewer));
    assert.equal(state.status, 200);
    const users = await sendJson('GET', `${daemon.url}/api/v1/users`, undefined, undefined, bearer(tokens.viewer));
    assert.equal(users.status, 403);
    const hardware = await sendJson('GET', `${daemon.url}/api/v1/devices/hardware`, undefined, undefined,
      bearer(tokens.viewer));
    assert.equal(hardware.status, 403);
    const anonymous = await sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, none);
    assert.equal(anonymous.status, 401);
    // Health and the contract stay open, for monitoring and for clients.
    assert.equal((await sendJson('GET', `${daemon.url}/api/v1/health`, undefined, undefined, none)).status, 200);
    assert.equal((await sendJson('GET', `${daemon.url}/api/v1/openapi.json`, undefined, undefined, none)).status, 200);
  });

  test('a token works until it is revoked, and its last use is shown', async () => {
    const made = await postJson(`${daemon.url}/api/v1/tokens`, { name: 'lift-controller', role: 'operator' });
    assert.equal(made.status, 201, JSON.stringify(made.body));
    api.check('Token', made.body);
    assert.match(made.body.token, /^cor_/);
    const use = () => sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, bearer(made.body.token));
    assert.equal((await use()).status, 200);
    const listed = await getJson(`${daemon.url}/api/v1/tokens`);
    const mine = listed.body.tokens.find((t) => t.id === made.body.id);
    assert.equal(mine.token, undefined, 'the secret is shown once');
    assert.ok(mine.last_used, 'last use recorded');
    assert.equal((await sendJson('DELETE', `${daemon.url}/api/v1/tokens/${made.body.id}`)).status, 204);
    const refused = await use();
    assert.equal(refused.status, 401);
    assert.equal(refused.body.code, 'invalid_token');
  });

  test('sessions: log in, writes only from the same origin, log out', async () => {
    const cookie = await logIn(daemon.url, 'admin1', 'admin-password');
    const me = await sendJson('GET', `${daemon.url}/api/v1/session`, undefined, undefined, { Cookie: cookie });
    assert.equal(me.status, 200);
    api.check('Principal', me.body);
    assert.deepEqual([me.body.name, me.body.role], ['admin1', 'admin']);
    // Where the robot stands is free floor on any map.
    const { pose } = (await sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, { Cookie: cookie })).body;
    const place = { name: 'lobby', x: pose.x, y: pose.y, yaw: 0 };
    const foreign = await sendJson('POST', `${daemon.url}/api/v1/places`, place, 'application/json',
      { Cookie: cookie, Origin: 'http://evil.example' });
    assert.equal(foreign.status, 403);
    assert.equal(foreign.body.code, 'cross_site');
    const noOrigin = await sendJson('POST', `${daemon.url}/api/v1/places`, place, 'application/json', { Cookie: cookie });
    assert.equal(noOrigin.status, 403, 'a cookie write without Origin is refused');
    const own = await sendJson('POST', `${daemon.url}/api/v1/places`, place, 'application/json',
      { Cookie: cookie, Origin: daemon.url });
    assert.equal(own.status, 201, JSON.stringify(own.body));
    const out = await sendJson('DELETE', `${daemon.url}/api/v1/session`, undefined, undefined, { Cookie: cookie });
    assert.equal(out.status, 204);
    const after = await sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, { Cookie: cookie });
    assert.equal(after.status, 401, 'the session is gone');
  });

  test('the WebSocket refuses a foreign Origin and anonymous callers; teleop over it needs an operator', async () => {
    const wsUrl = `${daemon.url.replace('http', 'ws')}/api/v1/stream`;
    const refusal = (headers) => new Promise((resolve) => {
      const ws = new WebSocket(wsUrl, { headers });
      ws.on('unexpected-response', (req, res) => resolve(res.statusCode));
      ws.on('open', () => { ws.close(); resolve(101); });
      ws.on('error', () => undefined);
    });
    assert.equal(await refusal({ ...bearer(tokens.viewer), Origin: 'http://evil.example' }), 403);
    assert.equal(await refusal({ Origin: daemon.url.replace('127.0.0.1', 'localhost') }), 403);
    assert.equal(await refusal({ ...bearer(tokens.viewer), Origin: daemon.url }), 101);
    const ws = new WebSocket(wsUrl, { headers: bearer(tokens.viewer) });
    const replies = [];
    ws.on('message', (d) => { const m = JSON.parse(String(d)); if (m.type) replies.push(m); });
    await new Promise((resolve) => ws.once('open', resolve));
    ws.send(JSON.stringify({ type: 'teleop', linear_mps: 0.1, angular_rps: 0 }));
    await waitFor(() => replies, (r) => r.length > 0, 5000, 'a reply to the teleop');
    ws.close();
    assert.equal(replies[0].type, 'error');
    assert.equal(replies[0].status, 403);
  });

  test('the audit log records who drew a zone, and who was refused', async () => {
    const polygon = [[1, 1], [2, 1], [2, 2], [1, 2]];
    const zone = { name: 'wet floor', kind: 'keep_out', polygon };
    const refused = await sendJson('POST', `${daemon.url}/api/v1/zones`, zone, 'application/json',
      bearer(tokens.operator));
    assert.equal(refused.status, 403);
    const cookie = await logIn(daemon.url, 'admin1', 'admin-password');
    const drawn = await sendJson('POST', `${daemon.url}/api/v1/zones`, zone, 'application/json',
      { Cookie: cookie, Origin: daemon.url });
    assert.equal(drawn.status, 201, JSON.stringify(drawn.body));
    const audit = await getJson(`${daemon.url}/api/v1/audit`);
    assert.equal(audit.status, 200);
    for (const r of audit.body.records) api.check('AuditRecord', r);
    const zoneWrites = audit.body.records.filter((r) => r.path === '/api/v1/zones' && r.method === 'POST');
    const byOperator = zoneWrites.find((r) => r.who === 'token:operator');
    const byAdmin = zoneWrites.find((r) => r.who === 'admin1');
    assert.equal(byOperator?.status, 403);
    assert.equal(byAdmin?.status, 201);
    assert.equal(byAdmin.detail, drawn.body.id);
    assert.equal(byAdmin.client, '127.0.0.1');
    // Only admins read it.
    const asOperator = await sendJson('GET', `${daemon.url}/api/v1/audit`, undefined, undefined, bearer(tokens.operator));
    assert.equal(asOperator.status, 403);
  });

  test('the console logs in, shows the role and disables what a viewer may not do', async () => {
    const browser = await launchBrowser();
    try {
      const page = await browser.newPage();
      await gotoConsole(page, daemon.url, { username: 'viewer1', password: 'viewer-password' });
      await page.getByTestId('user').filter({ hasText: 'viewer1 (viewer)' }).waitFor();
      assert.equal(await page.locator('[data-tool="keep_out"]').isDisabled(), true);
      assert.equal(await page.locator('[data-tool="goal"]').isDisabled(), true);
      assert.equal(await page.getByTestId('admin-link').isVisible(), false);
      await page.getByTestId('logout').click();
      await page.getByTestId('login-username').waitFor();
      // A wrong password is said so in the form.
      await page.getByTestId('login-username').fill('viewer1');
      await page.getByTestId('login-password').fill('not-the-password');
      await page.getByTestId('login-submit').click();
      await page.getByTestId('login-error').filter({ hasText: 'wrong username or password' }).waitFor();
    } finally {
      await browser.close();
    }
  });
  test('the admin page adds a user, makes and revokes a token, lists devices, and shows the audit log', async () => {
    const browser = await launchBrowser();
    try {
      const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
      const errors = [];
      page.on('pageerror', (e) => errors.push(e.message));
      await gotoConsole(page, daemon.url, { username: 'admin1', password: 'admin-password' });
      await page.getByTestId('admin-link').click();
      await page.getByTestId('users').filter({ hasText: 'viewer1' }).waitFor();
      await page.getByTestId('user-name').fill('night-shift');
      await page.getByTestId('user-password').fill('night-shift-password');
      await page.getByTestId('user-role').selectOption('operator');
      await page.getByTestId('user-add').click();
      await page.getByTestId('users').filter({ hasText: 'night-shift' }).waitFor();
      await page.getByTestId('token-name').fill('door-controller');
      await page.getByTestId('token-add').click();
      const shown = await page.getByTestId('token-secret').filter({ hasText: 'cor_' }).textContent();
      const secret = /cor_[A-Za-z0-9_-]+/.exec(shown)[0];
      const use = () => sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, bearer(secret));
      assert.equal((await use()).status, 200);
      await page.getByTestId('revoke-door-controller').click();
      await page.waitForFunction(() => !document.getElementById('tokens').textContent.includes('door-controller'));
      assert.equal((await use()).status, 401);
      await page.getByTestId('audit').filter({ hasText: 'POST /api/v1/users' }).waitFor();
      await page.getByTestId('audit').filter({ hasText: 'DELETE /api/v1/tokens' }).waitFor();
      // What is plugged in: this machine has no robot devices, and says so.
      await page.getByTestId('hardware').filter({ hasText: 'nothing plugged in' }).waitFor();
      // The simulated camera's mounting measured from the floor ahead (its configuration is not written here: the
      // daemon runs on the tree's own file).
      await page.getByTestId('camera-measure').click();
      await page.getByTestId('camera-calibration').filter({ hasText: /height 0\.\d+ m .*tilt \d+\.\d°/ }).waitFor();
      assert.equal(await page.getByTestId('camera-keep').isVisible(), true);
      // The laser's yaw against the camera (the simulator's laser faces forward as configured); a wheel run finished
      // where it started is no run, and the page says what to do.
      await page.getByTestId('laser-measure').click();
      await page.getByTestId('laser-calibration').filter({ hasText: /yaw -?0\.\d° \(configured 0\.0\), \d+ points/ }).waitFor();
      assert.equal(await page.getByTestId('laser-keep').isVisible(), true);
      await page.getByTestId('wheels-start').click();
      await page.getByTestId('wheels-calibration').filter({ hasText: /^started: drive straight/ }).waitFor();
      await page.getByTestId('wheels-finish').click();
      await page.getByTestId('wheels-calibration').filter({ hasText: /odometry shows 0\.00 m .*drive straight at least/ }).waitFor();
      assert.equal(await page.getByTestId('wheels-keep').isVisible(), false);
      // The live view: each slot's driver and health, the base's motion; a jog turns the robot through teleop.
      await page.locator('#live summary').click();
      await page.locator('#slots').filter({ hasText: /laser\s*sim/ }).waitFor();
      await page.getByTestId('live-base').filter({ hasText: /^base: -?0\.00 m\/s/ }).waitFor();
      await page.getByTestId('jog-left').click();
      await page.getByTestId('live-base').filter({ hasText: /m\/s, 0\.[1-9]\d rad\/s/ }).waitFor({ timeout: 5000 });
      await page.waitForFunction(() => document.getElementById('live-depth').naturalWidth > 0);
      assert.deepEqual(errors, []);
      // A viewer is sent back to the console.
      const other = await browser.newPage();
      await gotoConsole(other, daemon.url, { username: 'viewer1', password: 'viewer-password' });
      await other.goto(`${daemon.url}/admin`);
      await other.waitForURL(`${daemon.url}/`);
    } finally {
      await browser.close();
    }
  });
});

// Issue 39: webhooks made, tested and deleted from the admin page (against a real receiver on loopback), and the
// audit log filtered and paged there.
describe('the admin page\'s webhooks and audit log', () => {
  let daemon;
  before(async () => {
    daemon = await startDaemon();
    await postJson(`${daemon.url}/api/v1/users`, { username: 'admin2', password: 'admin-password', role: 'admin' });
  });
  after(async () => { await daemon?.stop(); });

  test('a webhook is added, tested against a receiver and deleted; the audit log is filtered and paged', async () => {
    const received = [];
    const receiver = createServer((req, res) => {
      let body = '';
      req.on('data', (c) => { body += c; });
      req.on('end', () => { received.push({ event: req.headers['x-corridor-event'], body }); res.end(); });
    });
    await new Promise((r) => receiver.listen(0, '127.0.0.1', r));
    const browser = await launchBrowser();
    try {
      const page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
      const errors = [];
      page.on('pageerror', (e) => errors.push(e.message));
      await gotoConsole(page, daemon.url, { username: 'admin2', password: 'admin-password' });
      await page.goto(`${daemon.url}/admin`);
      const url = `http://127.0.0.1:${receiver.address().port}/hook`;
      await page.getByTestId('webhook-url').fill(url);
      await page.getByTestId('webhook-events').getByLabel('bump').uncheck();
      await page.getByTestId('webhook-description').fill('the front desk');
      await page.getByTestId('webhook-add').click();
      await page.getByTestId('webhook-secret').filter({ hasText: 'signing secret' }).waitFor();
      const { body } = await getJson(`${daemon.url}/api/v1/webhooks`);
      const hook = body.webhooks.find((w) => w.url === url);
      assert.ok(hook && !hook.events.includes('bump') && hook.events.includes('waiting'), JSON.stringify(body));
      await page.getByTestId(`test-webhook-${hook.id}`).click();
      await waitFor(async () => received.length, (n) => n >= 1, 10000, 'the test delivery');
      assert.equal(received[0].event, 'ping');
      await page.getByTestId('webhooks').filter({ hasText: 'ping delivered' }).waitFor({ timeout: 10000 });
      await page.getByTestId(`delete-webhook-${hook.id}`).click();
      await page.waitForFunction((u) => !document.getElementById('webhooks').textContent.includes(u), url);

      // The audit log: 60 refused writes by a viewer's token make more than a page; filtered to failures, paged back.
      const viewer = mintToken(daemon.stateDir, 'viewer', 'audit-viewer');
      for (let i = 0; i < 60; ++i) {
        await sendJson('POST', `${daemon.url}/api/v1/places`, { name: `p${i}`, x: 1, y: 1 }, undefined, bearer(viewer));
      }
      await page.getByTestId('audit-who').fill('token:audit-viewer');
      await page.getByTestId('audit-failed').check();
      await page.getByTestId('audit-apply').click();
      await page.getByTestId('audit-page').filter({ hasText: '50 record(s)' }).waitFor();
      assert.equal(await page.locator('#audit tr').count(), 50);
      assert.equal(await page.locator('#audit tr', { hasText: '403' }).count(), 50);
      await page.getByTestId('audit-older').click();
      await page.getByTestId('audit-page').filter({ hasText: '10 record(s), page 2' }).waitFor();
      assert.equal(await page.getByTestId('audit-older').isDisabled(), true);
      await page.getByTestId('audit-newer').click();
      await page.getByTestId('audit-page').filter({ hasText: /^50 record/ }).waitFor();
      await page.getByTestId('audit-path').fill('webhooks');
      await page.getByTestId('audit-who').fill('');
      await page.getByTestId('audit-failed').uncheck();
      await page.getByTestId('audit-apply').click();
      await page.locator('#audit tr', { hasText: 'POST /api/v1/webhooks' }).first().waitFor();
      assert.equal(await page.locator('#audit tr', { hasText: '/api/v1/places' }).count(), 0);
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
      receiver.close();
    }
  });
});

describe('wrong passwords', () => {
  let daemon;
  before(async () => {
    daemon = await startDaemon();
    await postJson(`${daemon.url}/api/v1/users`, { username: 'operator1', password: 'operator-password', role: 'operator' });
  });
  after(async () => { await daemon?.stop(); });

  test('the 11th wrong password in a minute is refused with 429, even for the right one', async () => {
    for (let i = 0; i < 10; ++i) {
      const wrong = await postJson(`${daemon.url}/api/v1/session`, { username: 'operator1', password: `guess-${i}` });
      assert.equal(wrong.status, 401);
    }
    const limited = await postJson(`${daemon.url}/api/v1/session`, { username: 'operator1', password: 'operator-password' });
    assert.equal(limited.status, 429);
    assert.equal(limited.body.code, 'rate_limited');
    const retry = await fetch(`${daemon.url}/api/v1/session`, {
      method: 'POST', headers: { 'Content-Type': 'application/json' },
      body: JSON.stringify({ username: 'someone-else', password: 'x' }),
    });
    assert.equal(retry.status, 429, 'the client is limited, whatever the name');
    const after = Number(retry.headers.get('retry-after'));
    assert.ok(after > 0 && after <= 60, `Retry-After ${after}`);
  });
});

describe('first start: the setup code', () => {
  let daemon;
  before(async () => { daemon = await startDaemon(); });
  after(async () => { await daemon?.stop(); });

  test('is in the journal and on the robot\'s screen, makes the first admin once, and is not sent elsewhere', async () => {
    const status = await sendJson('GET', `${daemon.url}/api/v1/setup`, undefined, undefined, none);
    api.check('SetupStatus', status.body);
    assert.equal(status.body.needed, true);
    const code = status.body.code;  // the test runs on the robot: loopback is its own screen
    assert.match(code, /^[2-9A-Z]{4}-[2-9A-Z]{4}$/);
    assert.match(daemon.log(), new RegExp(`setup code ${code}`));
    const wrong = await sendJson('POST', `${daemon.url}/api/v1/setup`,
      { code: 'AAAA-AAAA', username: 'root', password: 'a-long-password' }, 'application/json', none);
    assert.equal(wrong.status, 403);
    const weak = await sendJson('POST', `${daemon.url}/api/v1/setup`,
      { code, username: 'root', password: 'short' }, 'application/json', none);
    assert.equal(weak.status, 422);
    const done = await sendJson('POST', `${daemon.url}/api/v1/setup`,
      { code: code.toLowerCase(), username: 'root', password: 'a-long-password' }, 'application/json', none);
    assert.equal(done.status, 201, JSON.stringify(done.body));
    assert.deepEqual([done.body.name, done.body.role], ['root', 'admin']);
    const again = await sendJson('POST', `${daemon.url}/api/v1/setup`,
      { code, username: 'root2', password: 'a-long-password' }, 'application/json', none);
    assert.equal(again.status, 409);
    const after = await sendJson('GET', `${daemon.url}/api/v1/setup`, undefined, undefined, none);
    assert.deepEqual(after.body, { needed: false, session: null });
    // The last admin cannot be deleted.
    const last = await sendJson('DELETE', `${daemon.url}/api/v1/users/root`);
    assert.equal(last.status, 409);
  });
});

describe('first start in the console', () => {
  let daemon;
  before(async () => { daemon = await startDaemon(); });
  after(async () => { await daemon?.stop(); });

  test('asks for the setup code and makes the first admin', async () => {
    const code = (await sendJson('GET', `${daemon.url}/api/v1/setup`, undefined, undefined, none)).body.code;
    const browser = await launchBrowser();
    try {
      const page = await browser.newPage();
      await page.goto(daemon.url);
      await page.getByTestId('login-code').waitFor();
      await page.getByTestId('login-code').fill('WRONG-CODE');
      await page.getByTestId('login-username').fill('first-admin');
      await page.getByTestId('login-password').fill('first-admin-password');
      await page.getByTestId('login-submit').click();
      await page.getByTestId('login-error').filter({ hasText: 'Wrong setup code' }).waitFor();
      await page.getByTestId('login-code').fill(code);
      await page.getByTestId('login-submit').click();
      await page.getByTestId('connection').filter({ hasText: 'connected' }).waitFor({ timeout: 15000 });
      await page.getByTestId('user').filter({ hasText: 'first-admin (admin)' }).waitFor();
      assert.equal(await page.getByTestId('admin-link').isVisible(), true);
    } finally {
      await browser.close();
    }
  });
});

describe('auth.anonymous_viewer', () => {
  let daemon;
  before(async () => {
    const dir = mkdtempSync(join(tmpdir(), 'corridor-room-'));
    daemon = await startDaemon({ config: `sim:\n  world: "${writeRoom(dir, 4, 3)}"\n  start: {x_m: 1, y_m: 1, yaw_deg: 0}\nauth:\n  anonymous_viewer: true\n` });
  });
  after(async () => { await daemon?.stop(); });

  test('opens reads without login, not writes', async () => {
    assert.equal((await sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, none)).status, 200);
    const write = await sendJson('POST', `${daemon.url}/api/v1/teleop`, { linear_mps: 0, angular_rps: 0 },
      'application/json', none);
    assert.equal(write.status, 401);
    assert.ok(authHeaders(daemon.url).Authorization, 'the test still has its token');
  });
});

describe('the configuration through the API', () => {
  let daemon;
  let file;
  before(async () => {
    // A state directory of the test's own: it outlives the first daemon.
    const stateDir = mkdtempSync(join(tmpdir(), 'corridor-config-'));
    daemon = await startDaemon({
      stateDir, config: `sim:\n  world: "${writeRoom(stateDir, 4, 3)}"\n  start: {x_m: 1, y_m: 1, yaw_deg: 0}\n`,
    });
    file = join(stateDir, 'corridor.yaml');
  });
  after(async () => {
    await daemon?.stop();
    rmSync(daemon.stateDir, { recursive: true, force: true });
  });

  test('is read and changed by admins only, checked as at start-up, and rewritten whole', async () => {
    const operator = mintToken(daemon.stateDir, 'operator', 'config-operator');
    assert.equal((await sendJson('GET', `${daemon.url}/api/v1/config`, undefined, undefined, bearer(operator))).status, 403);
    const read = await getJson(`${daemon.url}/api/v1/config`);
    assert.equal(read.status, 200);
    assert.equal(read.body.file, file);
    assert.deepEqual(read.body.config.sim.start, { x_m: 1, y_m: 1, yaw_deg: 0 });

    const before = readFileSync(file, 'utf8');
    const bad = await sendJson('PATCH', `${daemon.url}/api/v1/config`, { auth: { session_hours: -1 } });
    assert.equal(bad.status, 422);
    assert.match(bad.body.detail, /auth\.session_hours/);
    const unknown = await sendJson('PATCH', `${daemon.url}/api/v1/config`, { auth: { sessions: 3 } });
    assert.equal(unknown.status, 422);
    assert.match(unknown.body.detail, /auth\.sessions/);
    assert.equal(readFileSync(file, 'utf8'), before, 'a refused change leaves the file alone');

    const changed = await sendJson('PATCH', `${daemon.url}/api/v1/config`,
      { server: { stream_rate_hz: 10 }, auth: { anonymous_viewer: true }, sim: { start: { yaw_deg: 90 } } });
    assert.equal(changed.status, 200, JSON.stringify(changed.body));
    assert.deepEqual(changed.body.changed.sort(), ['auth.anonymous_viewer', 'server.stream_rate_hz', 'sim.start.yaw_deg']);
    assert.equal(changed.body.restart_required, true);
    assert.deepEqual(changed.body.config.sim.start, { x_m: 1, y_m: 1, yaw_deg: 90 });
    // The rewritten file starts a daemon that has the change.
    await daemon.stop();
    daemon = await startDaemon({ stateDir: daemon.stateDir, args: ['--config', file] });
    const anonymous = await sendJson('GET', `${daemon.url}/api/v1/state`, undefined, undefined, none);
    assert.equal(anonymous.status, 200, 'anonymous_viewer is on after the restart');
    const audit = await getJson(`${daemon.url}/api/v1/audit`);
    assert.ok(audit.body.records.some((r) => r.method === 'PATCH' && r.path === '/api/v1/config' && r.status === 200));
  });
});
