// The battery and the charging dock in a 4 x 3 m room: docking through the API ends on the dock within 2 cm and
// 2 degrees (the simulator's truth) and charges; undocking, a mission from the dock, the face while charging, bad
// requests; and an idle robot low on charge going to its dock by itself. The robot's pose comes from wheel odometry
// with the simulator's default noise, so the map's idea of the dock drifts: docking finds the dock in the depth image.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  getJson, launchBrowser, openApiValidator, openConsole, postJson, sendJson, sleep, startDaemon, waitFor, writeRoom,
} from './daemon.mjs';

const api = openApiValidator();
const dock = { x: 3.2, y: 1.5, yaw: 0 };  // the docked pose: facing the room's east wall, its face 0.21 m ahead
const roomConfig = (world, extra = '') => `
sim:
  world: "${world}"
  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 90}
  camera: {width: 160, height: 120}
  dock: {enabled: true, x_m: ${dock.x}, y_m: ${dock.y}, yaw_deg: 0}
${extra}`;

const state = async (url) => {
  const { body } = await getJson(`${url}/api/v1/state`);
  api.check('State', body);
  return body;
};
const angleDiff = (a, b) => Math.atan2(Math.sin(a - b), Math.cos(a - b));
const finished = (s) => s.mission && ['succeeded', 'failed', 'canceled'].includes(s.mission.status);

describe('docking', () => {
  let daemon;
  let dir;
  before(async () => {
    dir = mkdtempSync(join(tmpdir(), 'corridor-dock-'));
    daemon = await startDaemon({ config: roomConfig(writeRoom(dir, 4, 3)) });
  });
  after(async () => {
    await daemon?.stop();
    rmSync(dir, { recursive: true, force: true });
  });

  test('the simulator\'s dock is a place of the map, with its staging pose', async () => {
    const { body } = await getJson(`${daemon.url}/api/v1/places`);
    api.check('Places', body);
    const docks = body.places.filter((p) => p.kind === 'dock');
    assert.equal(docks.length, 1, JSON.stringify(body));
    assert.equal(docks[0].name, 'dock');
    assert.ok(Math.abs(docks[0].x - dock.x) < 1e-9 && Math.abs(docks[0].y - dock.y) < 1e-9);
    assert.ok(Math.abs(docks[0].staging.x - (dock.x - 0.7)) < 1e-9, JSON.stringify(docks[0]));
    const s = await state(daemon.url);
    assert.equal(s.docked, false);
    assert.equal(s.battery.on_charger, false);
    assert.ok(s.battery.current_a < 0, 'draining');
  });

  test('bad docking requests are refused and move nothing', async () => {
    const cases = [
      ['/api/v1/dock', { dock: 'garage' }, 422, 'unknown_place'],
      ['/api/v1/dock', { dock: 7 }, 400, undefined],
      ['/api/v1/dock', { dock: 'dock', speed: 1 }, 400, undefined],
      ['/api/v1/undock', {}, 409, 'not_docked'],
      ['/api/v1/undock', { now: true }, 400, undefined],
    ];
    for (const [path, body, status, code] of cases) {
      const res = await postJson(`${daemon.url}${path}`, body);
      assert.equal(res.status, status, `${path} ${JSON.stringify(body)}: ${JSON.stringify(res.body)}`);
      api.check('Problem', res.body);
      if (code) assert.equal(res.body.code, code);
    }
    const place = await postJson(`${daemon.url}/api/v1/places`, { name: 'shed', x: 1, y: 1, kind: 'garage' });
    assert.equal(place.status, 400);
    assert.equal((await state(daemon.url)).mission, null, 'no mission started');
  });

  test('docks within 2 cm and 2 degrees, charges and looks sleepy; undocks; a mission from the dock backs off first',
    async () => {
      const res = await postJson(`${daemon.url}/api/v1/dock`, {});
      assert.equal(res.status, 201, JSON.stringify(res.body));
      api.check('Mission', res.body);
      assert.deepEqual(res.body.waypoints.map((w) => w.action), ['dock']);
      const phases = new Set();
      const done = await waitFor(() => state(daemon.url), (s) => {
        if (s.mission?.docking) phases.add(s.mission.docking);
        return finished(s);
      }, 90000, 'the docking to finish');
      assert.equal(done.mission.status, 'succeeded', done.mission.error);
      assert.ok(phases.has('approaching'), [...phases].join());
      const truth = done.sim_true_pose;
      const off = Math.hypot(truth.x - dock.x, truth.y - dock.y);
      const offDeg = Math.abs(angleDiff(truth.yaw, dock.yaw)) * 180 / Math.PI;
      assert.ok(off <= 0.02 && offDeg <= 2, `docked ${(off * 100).toFixed(1)} cm and ${offDeg.toFixed(2)} deg off`);
      assert.equal(done.docked, true);
      assert.equal(done.bumper_pressed, false, 'it stops short of the face, not against it');

      const charging = await waitFor(() => state(daemon.url), (s) => s.battery.on_charger && s.battery.charging,
        5000, 'the battery to charge');
      await waitFor(() => state(daemon.url), (s) => s.battery.percent > charging.battery.percent, 5000,
        'the charge to rise');
      await waitFor(() => state(daemon.url), (s) => s.face === 'sleepy', 5000, 'a sleepy face while charging');
      assert.equal((await postJson(`${daemon.url}/api/v1/dock`, {})).status, 409, 'docked already');

      // A mission from the dock: off the dock, then on.
      const goal = { x: 1.0, y: 2.0 };
      const m = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [goal] });
      assert.equal(m.status, 201, JSON.stringify(m.body));
      assert.deepEqual(m.body.waypoints.map((w) => w.action), ['undock', 'go']);
      const undocking = await waitFor(() => state(daemon.url), (s) => s.mission.docking === 'undocking', 5000,
        'undocking');
      assert.equal(undocking.mode, 'docking');
      const away = await waitFor(() => state(daemon.url), finished, 60000, 'the mission from the dock');
      assert.equal(away.mission.status, 'succeeded', away.mission.error);
      assert.equal(away.docked, false);
      assert.equal(away.battery.on_charger, false);
      assert.ok(Math.hypot(away.sim_true_pose.x - goal.x, away.sim_true_pose.y - goal.y) < 0.1);
    });

  test('undocking on its own backs straight off to the staging pose', async () => {
    const docked = await postJson(`${daemon.url}/api/v1/dock`, { dock: 'dock' });
    assert.equal(docked.status, 201, JSON.stringify(docked.body));
    const on = await waitFor(() => state(daemon.url), finished, 90000, 'docking again');
    assert.equal(on.mission.status, 'succeeded', on.mission.error);
    const res = await sendJson('POST', `${daemon.url}/api/v1/undock`);
    assert.equal(res.status, 201, JSON.stringify(res.body));
    const off = await waitFor(() => state(daemon.url), finished, 30000, 'undocking');
    assert.equal(off.mission.status, 'succeeded', off.mission.error);
    const t = off.sim_true_pose;
    assert.ok(Math.abs(t.x - (dock.x - 0.7)) < 0.05 && Math.abs(t.y - dock.y) < 0.03, JSON.stringify(t));
    assert.equal(off.docked, false);
  });

  test('the console shows the battery and the dock, and docks with its button', async () => {
    const browser = await launchBrowser();
    try {
      const { page, errors } = await openConsole(browser, daemon.url);
      await page.getByTestId('battery').filter({ hasText: /\d+ %/ }).waitFor({ timeout: 5000 });
      await page.locator('.place-label.dock').waitFor({ timeout: 5000 });
      await page.getByTestId('dock').click();
      await page.getByTestId('mission-status').filter({ hasText: /docking: (seeking|approaching|final)/ })
        .waitFor({ timeout: 30000 });
      await page.getByTestId('battery').filter({ hasText: 'charging' }).waitFor({ timeout: 60000 });
      await page.locator('[data-testid=undock]:enabled').waitFor({ timeout: 30000 });  // docked: it may back off
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
});

describe('going to charge', () => {
  test('an idle robot below docking.charge_below_percent goes to its dock by itself', async () => {
    const dir = mkdtempSync(join(tmpdir(), 'corridor-charge-'));
    const daemon = await startDaemon({
      config: roomConfig(writeRoom(dir, 4, 3), `  battery: {initial_percent: 15}
docking:
  charge_below_percent: 20
`),
    });
    try {
      const s = await waitFor(() => state(daemon.url), (x) => x.mission !== null, 10000, 'a mission to charge');
      assert.deepEqual(s.mission.waypoints.map((w) => w.action), ['dock']);
      assert.equal(s.mission.waypoints[0].place, 'dock');
      const done = await waitFor(() => state(daemon.url), finished, 90000, 'the docking to finish');
      assert.equal(done.mission.status, 'succeeded', done.mission.error);
      await waitFor(() => state(daemon.url), (x) => x.battery.charging, 5000, 'charging');
      await sleep(500);
    } finally {
      await daemon.stop();
      rmSync(dir, { recursive: true, force: true });
    }
  });
});
