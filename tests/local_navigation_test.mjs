// Local navigation in the daemon: a mission whose planned path runs through something the map does not show, and
// simulated people. The world is a 10 x 6 m room written here as a map_server map; the obstacles and people exist
// only in the simulator, so the planner plans straight through them and the robot must see them with its camera.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  apiFetch, getJson, gotoConsole, launchBrowser, openApiValidator, postJson, sendJson, sleep, startDaemon, waitFor,
  writeRoom,
} from './daemon.mjs';

const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;

const api = openApiValidator();

const dir = mkdtempSync(join(tmpdir(), 'corridor-room-'));
const room = writeRoom(dir, 10, 6);
after(() => rmSync(dir, { recursive: true, force: true }));
// The room, the robot at its west end looking east, `sim` keys of the test's own, and the laser's driver.
const roomConfig = (sim, laser = 'sim') => `
devices: {laser: {driver: ${laser}}}
sim:
  world: "${room}"
  start: {x_m: 1.5, y_m: 3.0, yaw_deg: 0}
${sim}`;

describe('local navigation among unmapped obstacles and people', () => {
  const pillar = { x: 5.0, y: 3.05, r: 0.3 };
  let daemon;
  before(async () => {
    daemon = await startDaemon({ config: roomConfig(`
  camera: {rate_hz: 15}
  obstacles:
    - {shape: cylinder, x_m: ${pillar.x}, y_m: ${pillar.y}, size_m: ${pillar.r}, height_m: 1.0}
# The 3D map would put the pillar in the planner's costmap once seen: this is about what the planner does not know.
octomap: {costmap_layer: false}
`, 'none') });
    await sleep(300);
  });
  after(async () => { await daemon?.stop(); });

  test('a pillar on the planned path is passed around by MORP-RB, at the camera rate', async () => {
    const start = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 8.5, y: 3.0 }] });
    assert.equal(start.status, 201, JSON.stringify(start.body));
    // The plan goes straight through the pillar: the map does not know it.
    assert.ok(start.body.status === 'active');
    const policies = new Set();
    let closest = Infinity;
    let bumped = false;
    let doc;
    const deadline = Date.now() + 90000;
    for (;;) {
      const s = (await getJson(`${daemon.url}/api/v1/state`)).body;
      if (s.mission) policies.add(s.mission.policy);
      bumped ||= s.bumper_pressed;
      if (s.sim_true_pose) closest = Math.min(closest, Math.hypot(s.sim_true_pose.x - pillar.x, s.sim_true_pose.y - pillar.y));
      doc = s.mission;
      if (doc && doc.status !== 'active') break;
      assert.ok(Date.now() < deadline, `mission still ${doc?.status}, policy ${doc?.policy}`);
      await sleep(100);
    }
    assert.equal(doc.status, 'succeeded', JSON.stringify(doc));
    assert.ok(!bumped, 'the bumper was pressed');
    assert.ok(closest > pillar.r + 0.2, `came within ${closest.toFixed(2)} m of the pillar's centre`);
    assert.ok([...policies].some((p) => p.startsWith('change_lane') || p === 'stop_and_turn'),
      `MORP-RB never took over: ${[...policies]}`);
    // Commands followed the camera's frames, and the console can show how fast.
    const s = (await getJson(`${daemon.url}/api/v1/state`)).body;
    api.check('State', s);
    assert.ok(s.control_latency.samples > 100, JSON.stringify(s.control_latency));
    assert.equal(s.sim_obstacles.length, 1);
    assert.equal(s.sim_obstacles[0].shape, 'cylinder');
  });

  test('the camera stops answering: the robot stops at once, and goes on when it is back', async (t) => {
    const res = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 6.5, y: 1.0 }] });
    assert.equal(res.status, 201, JSON.stringify(res.body));
    await waitFor(() => state(daemon.url), (s) => s.velocity.linear_mps > 0.2, 20000, 'the robot driving');
    const fault = await sendJson('PUT', `${daemon.url}/api/v1/sim/faults`, { camera_stopped: true });
    assert.equal(fault.status, 200, JSON.stringify(fault.body));
    api.check('SimFaults', fault.body);
    const t0 = Date.now();
    const stopped = await waitFor(() => state(daemon.url), (s) => Math.abs(s.velocity.linear_mps) < 0.005, 3000,
      'the robot stopping');
    t.diagnostic(`stopped ${Date.now() - t0} ms after the camera stopped`);
    assert.equal(stopped.mission.status, 'active');
    await sleep(1000);
    const still = await state(daemon.url);
    assert.ok(Math.abs(still.velocity.linear_mps) < 0.005, 'it stays stopped without frames');
    assert.equal(still.mission.policy, 'waiting_for_depth');
    // Bad requests change nothing.
    assert.equal((await sendJson('PUT', `${daemon.url}/api/v1/sim/faults`, { camera_stopped: 'yes' })).status, 400);
    assert.equal((await sendJson('PUT', `${daemon.url}/api/v1/sim/faults`, { lidar: true })).status, 400);
    assert.equal((await sendJson('PUT', `${daemon.url}/api/v1/sim/faults`, { camera_stopped: false })).status, 200);
    const done = await waitFor(() => state(daemon.url), (s) => s.mission.status !== 'active', 60000, 'the mission');
    assert.equal(done.mission.status, 'succeeded', JSON.stringify(done.mission));
  });
});

describe('simulated people', () => {
  let daemon;
  before(async () => {
    daemon = await startDaemon({ config: roomConfig(`
  camera: {width: 160, height: 120}
  pedestrians: 2
tracking:
  traffic: {weight: 10, lane_half_width_m: 0.5}  # decisive on the short stretch the plan test watches
`) });
  });
  after(async () => { await daemon?.stop(); });

  test('walk, and are in the state for the console', async () => {
    const first = (await getJson(`${daemon.url}/api/v1/state`)).body;
    api.check('State', first);
    await sleep(1000);
    const later = (await getJson(`${daemon.url}/api/v1/state`)).body;
    assert.equal(first.sim_pedestrians.length, 2);
    const moved = later.sim_pedestrians.some((p, i) =>
      Math.hypot(p.x - first.sim_pedestrians[i].x, p.y - first.sim_pedestrians[i].y) > 0.2);
    assert.ok(moved, JSON.stringify([first.sim_pedestrians, later.sim_pedestrians]));
  });

  test('are tracked by the laser, with their velocities', async () => {
    // A person walking in view of the laser shows as a moving object near them, going their way at their speed
    // (the laser sees a person's near side, and the state's two lists are a scan apart: hence the tolerances).
    const matches = (st) => st.sim_pedestrians.some((p) => Math.hypot(p.vx, p.vy) > 0.4 && st.tracked_objects.some((o) =>
      o.moving && Math.hypot(o.x - p.x, o.y - p.y) < 0.5 && Math.hypot(o.vx - p.vx, o.vy - p.vy) < 0.3));
    const last = await waitFor(() => state(daemon.url), matches, 8000, 'a tracked person');
    api.check('State', last);
    const tracking = last.nodes.find((n) => n.name === 'tracking');
    assert.equal(tracking?.health, 'ok', JSON.stringify(tracking));
  });

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

  test('leave their mark on plans: a path along where someone walks keeps beside their way', async () => {
    // Watch a walking person for 3 s: every place they pass is on their way. A plan from one end of what they
    // walked to the other would run straight along it; with the laser's traffic costs it keeps to one side.
    const walking = await waitFor(() => state(daemon.url), (st) => st.sim_pedestrians.some((p) => Math.hypot(p.vx, p.vy) > 0.5),
      8000, 'a walking person');
    const who = walking.sim_pedestrians.findIndex((p) => Math.hypot(p.vx, p.vy) > 0.5);
    const seen = [];
    for (let i = 0; i < 12; i += 1) {
      const p = (await state(daemon.url)).sim_pedestrians[who];
      seen.push({ x: p.x, y: p.y });
      await sleep(250);
    }
    let a = seen[0];
    let b = seen[0];
    for (const p of seen) for (const q of seen) if (Math.hypot(p.x - q.x, p.y - q.y) > Math.hypot(a.x - b.x, a.y - b.y)) [a, b] = [p, q];
    const walked = Math.hypot(a.x - b.x, a.y - b.y);
    assert.ok(walked > 1.2, `the person walked only ${walked.toFixed(2)} m`);
    await sleep(1500);  // the tracker hands its traffic costs to the planner every second
    const plan = await postJson(`${daemon.url}/api/v1/plan`, { start: a, goal: b });
    assert.equal(plan.status, 200, JSON.stringify(plan.body));
    // How far the path's corners stray from the straight line a-b.
    const off = (p) => Math.abs((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / walked;
    const farthest = Math.max(...plan.body.path.map(off));
    assert.ok(farthest > 0.4, `the plan runs along their way: ${JSON.stringify(plan.body.path)}`);
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

describe('simulated people, a robot without a laser: tracked with its camera', () => {
  let daemon;
  before(async () => {
    daemon = await startDaemon({ config: roomConfig(`
  camera: {width: 160, height: 120}
  pedestrians: 2
`, 'none') });
  });
  after(async () => { await daemon?.stop(); });

  test('are tracked in the depth camera\'s view, with their velocities', async () => {
    // The robot looks down the room: a person walking in front of it shows as a moving object near them, going their
    // way (the camera sees a person's near side, and the state's two lists are a frame apart: hence the tolerances).
    const inView = (st, p) => {
      const pose = st.sim_true_pose;
      const bearing = Math.atan2(p.y - pose.y, p.x - pose.x) - pose.yaw;
      return Math.abs(Math.atan2(Math.sin(bearing), Math.cos(bearing))) < 0.6 && Math.hypot(p.x - pose.x, p.y - pose.y) < 5;
    };
    const matches = (st) => st.sim_pedestrians.some((p) => inView(st, p) && Math.hypot(p.vx, p.vy) > 0.4 &&
      st.tracked_objects.some((o) => o.moving && Math.hypot(o.x - p.x, o.y - p.y) < 0.6 &&
        Math.hypot(o.vx - p.vx, o.vy - p.vy) < 0.4));
    const last = await waitFor(() => state(daemon.url), matches, 20000, 'a person tracked by the camera');
    api.check('State', last);
    const tracking = last.nodes.find((n) => n.name === 'tracking');
    assert.equal(tracking?.health, 'ok', JSON.stringify(tracking));
  });

  test('who walks out of the camera\'s view is still there, where they are expected, not seen', async () => {
    // A person beside the robot, out of the camera's 85 degrees, with a moving track near them that says it is not
    // seen: kept on its prediction (tracking.unseen_coast_s) rather than forgotten.
    const outOfView = (st, p) => {
      const pose = st.sim_true_pose;
      const bearing = Math.atan2(p.y - pose.y, p.x - pose.x) - pose.yaw;
      return Math.abs(Math.atan2(Math.sin(bearing), Math.cos(bearing))) > 0.9 && Math.hypot(p.x - pose.x, p.y - pose.y) < 4;
    };
    const kept = (st) => st.sim_pedestrians.some((p) => outOfView(st, p) &&
      st.tracked_objects.some((o) => o.moving && !o.seen && Math.hypot(o.x - p.x, o.y - p.y) < 0.8));
    const last = await waitFor(() => state(daemon.url), kept, 40000, 'a person out of view, still tracked');
    api.check('State', last);
  });
});
