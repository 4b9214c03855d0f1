// The battery and the charging dock in a 4 x 3 m room, over the daemon's real HTTP API and in the console: the dock as
// a place with its staging pose, bad docking requests refused with the problem's code, the battery and the dock in
// the console, and its dock button starting a docking. How docking itself behaves (on the dock within 2 cm and
// 2 degrees, charging, undocking, a mission from the dock, going to charge when low) is tested in simulated time:
// tests/docking_lockstep_test.cc.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  getJson, launchBrowser, openApiValidator, openConsole, postJson, startDaemon, writeRoom,
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

  test('the console shows the battery and the dock, and its dock button starts a docking', async () => {
    const browser = await launchBrowser();
    try {
      const { page, errors } = await openConsole(browser, daemon.url);
      await page.getByTestId('battery').filter({ hasText: /\d+ %/ }).waitFor({ timeout: 5000 });
      await page.locator('.place-label.dock').waitFor({ timeout: 5000 });
      await page.locator('[data-testid=undock]:disabled').waitFor({ timeout: 5000 });  // not docked
      await page.getByTestId('dock').click();
      await page.getByTestId('mission-status').filter({ hasText: /docking: (seeking|approaching|final)/ })
        .waitFor({ timeout: 30000 });
      assert.deepEqual((await state(daemon.url)).mission.waypoints.map((w) => w.action), ['dock']);
      await page.locator('#mission-cancel').click();
      await page.getByTestId('mission-status').filter({ hasText: /^canceled/ }).waitFor({ timeout: 5000 });
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });
});
