// Simulated people in the console, through a real daemon: the people and the laser's moving tracks drawn, the end of a
// walk drawn where someone walks to it, and where people walk laid over the map (the traffic image over HTTP). The
// behaviour itself (a pillar passed round, a silent camera, tracking by laser and camera, walk ends, traffic in
// plans) is tests/local_navigation_lockstep_test.cc, in simulated time. The world is a 10 x 6 m room written here as a
// map_server map.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  apiFetch, getJson, gotoConsole, launchBrowser, openApiValidator, startDaemon, waitFor, writeRoom,
} from './daemon.mjs';

const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;

const api = openApiValidator();

const dir = mkdtempSync(join(tmpdir(), 'corridor-room-'));
const room = writeRoom(dir, 10, 6);
after(() => rmSync(dir, { recursive: true, force: true }));
describe('simulated people', () => {
  let daemon;
  before(async () => {
    // The room, the robot at its west end looking east, two people walking, the laser's traffic costs.
    daemon = await startDaemon({ config: `
sim:
  world: "${room}"
  start: {x_m: 1.5, y_m: 3.0, yaw_deg: 0}
  camera: {width: 160, height: 120}
  pedestrians: 2
tracking:
  traffic: {weight: 10, lane_half_width_m: 0.5}
` });
  });
  after(async () => { await daemon?.stop(); });

  test('are drawn in the console: the people, and the moving tracks of the laser', async () => {
    const browser = await launchBrowser();
    try {
      const page = await browser.newPage({ viewport: { width: 1024, height: 700 } });
      page.on('pageerror', (e) => { throw e; });
      await gotoConsole(page, daemon.url);
      await page.waitForFunction(() => document.querySelectorAll('path.sim-person').length === 2, null, { timeout: 10000 });
      await page.waitForFunction(() => document.querySelectorAll('path.tracked-moving').length > 0, null, { timeout: 10000 });
    } finally {
      await browser.close();
    }
  });

  test('turning round at the ends of their walks is remembered, and drawn where someone walks to one', async () => {
    // People pace between their two points: once a person has turned round at an end, walking back to it they are
    // reported with it ahead (the robot expects them to turn there), and the console draws a dotted line to it.
    const ahead = (st) => st.tracked_objects.some((o) => o.moving && o.walk_end &&
      (o.walk_end.x - o.x) * o.vx + (o.walk_end.y - o.y) * o.vy > 0);
    const st = await waitFor(() => state(daemon.url), ahead, 40000, 'a person with the end of their walk ahead');
    api.check('State', st);
    const browser = await launchBrowser();
    try {
      const page = await browser.newPage({ viewport: { width: 1024, height: 700 } });
      page.on('pageerror', (e) => { throw e; });
      await gotoConsole(page, daemon.url);
      await page.waitForFunction(() => document.querySelectorAll('path.tracked-walk-end').length > 0, null,
        { timeout: 20000 });
    } finally {
      await browser.close();
    }
  });

  test('where they walk is laid over the console\'s map', async () => {
    // The planner's traffic costs as a PNG the map image's size (people have walked by now: the test above); the
    // console shows it over the map.
    const map = (await getJson(`${daemon.url}/api/v1/map`)).body;
    const res = await apiFetch(`${daemon.url}/api/v1/map/traffic`);
    const png = Buffer.from(await res.arrayBuffer());
    assert.equal(res.status, 200, png.toString());
    assert.equal(res.headers.get('content-type'), 'image/png');
    assert.deepEqual([png.readUInt32BE(16), png.readUInt32BE(20)], [map.width, map.height], 'the PNG header\'s size');
    const browser = await launchBrowser();
    try {
      const page = await browser.newPage({ viewport: { width: 1024, height: 700 } });
      page.on('pageerror', (e) => { throw e; });
      await gotoConsole(page, daemon.url);
      await page.waitForFunction((w) => [...document.querySelectorAll('img.traffic-image')].some((img) =>
        img.complete && img.naturalWidth === w && img.style.opacity === '1'), map.width, { timeout: 15000 });
    } finally {
      await browser.close();
    }
  });
});
