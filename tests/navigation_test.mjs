// Planning and missions in a small real arena (lse_arena, 4 x 3 m): a lower room and two upper rooms joined by one
// 1.2 m doorway (x 0.8 to 2.0, y about 1.5). Odometry is noiseless here so that accuracy is the controller's.
import assert from 'node:assert/strict';
import { copyFileSync, mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import { getJson, openApiValidator, postJson, sendJson, sleep, sourceDir, startDaemon, waitFor } from './daemon.mjs';

const api = openApiValidator();
const config = `
devices: {laser: {driver: none}}
sim:
  world: "${sourceDir}tests/data/maps/lse_arena/lse_arena.yaml"
  start: {x_m: 1.0, y_m: 0.75, yaw_deg: 0}
  camera: {rate_hz: 15, width: 160, height: 120}
  base: {odom_linear_noise: 0, odom_angular_noise: 0}
`;
const upperRoom = { x: 1.0, y: 2.4 };
const doorway = [[0.7, 1.2], [2.1, 1.2], [2.1, 1.8], [0.7, 1.8]];

const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;
const mission = async (url, id) => {
  const res = await getJson(`${url}/api/v1/missions/${id}`);
  api.check('Mission', res.body);
  return res.body;
};
const degrees = (rad) => (rad * 180) / Math.PI;
const angleDiff = (a, b) => Math.atan2(Math.sin(a - b), Math.cos(a - b));

async function startMission(url, body) {
  const res = await postJson(`${url}/api/v1/missions`, body);
  assert.equal(res.status, 201, JSON.stringify(res.body));
  api.check('Mission', res.body);
  return res.body.id;
}

describe('missions in the arena', () => {
  let daemon;
  before(async () => { daemon = await startDaemon({ config }); await sleep(300); });
  after(async () => { await daemon?.stop(); });

  test('a plan over REST, without moving', async () => {
    const before = await state(daemon.url);
    const res = await postJson(`${daemon.url}/api/v1/plan`, { goal: { ...upperRoom, yaw: 1.0 } });
    assert.equal(res.status, 200, JSON.stringify(res.body));
    api.check('Plan', res.body);
    const { path } = res.body;
    assert.ok(Math.abs(path[0].x - 1.0) < 1e-6 && Math.abs(path[0].y - 0.75) < 1e-6, 'starts at the robot');
    assert.equal(path.at(-1).yaw, 1.0);
    // Through the doorway, which is the only way up: some leg crosses y = 1.5 between x = 0.8 and 2.0.
    const crossing = path.slice(1).some((b, i) => {
      const a = path[i];
      if ((a.y - 1.5) * (b.y - 1.5) > 0 || a.y === b.y) return false;
      const x = a.x + ((1.5 - a.y) * (b.x - a.x)) / (b.y - a.y);
      return x > 0.8 && x < 2.0;
    });
    assert.ok(crossing, JSON.stringify(path));
    assert.ok(res.body.min_clearance_m >= 0.2);
    const after = await state(daemon.url);
    assert.deepEqual(after.sim_true_pose, before.sim_true_pose, 'planning does not move the robot');
  });

  test('bad goals get 422 with the reason, before anything moves', async () => {
    const cases = [
      [{ goal: { x: -3, y: 1 } }, 'goal_outside_map'],
      [{ goal: { x: 0.02, y: 0.02 } }, 'goal_occupied'],  // in the outer wall
      [{ goal: { place: 'nowhere' } }, 'unknown_place'],
      [{ start: { x: 0.02, y: 1.0 }, goal: upperRoom }, 'start_occupied'],
    ];
    for (const [body, code] of cases) {
      const res = await postJson(`${daemon.url}/api/v1/plan`, body);
      assert.equal(res.status, 422, JSON.stringify(res.body));
      api.check('Problem', res.body);
      assert.equal(res.body.code, code);
    }
    const bad = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [upperRoom, { x: 9, y: 9 }] });
    assert.equal(bad.status, 422);
    assert.match(bad.body.detail, /waypoints\[1\]/);
    for (const body of [{ goal: { x: 'a', y: 1 } }, { goal: { x: 1 } }, { goal: { x: 1, y: 1, z: 2 } }, {}]) {
      assert.equal((await postJson(`${daemon.url}/api/v1/plan`, body)).status, 400, JSON.stringify(body));
    }
    assert.notEqual((await state(daemon.url)).mode, 'mission');
  });

  test('a goal over REST: the robot arrives within 2 cm and 2 degrees', async () => {
    const goal = { x: 3.0, y: 0.9, yaw: Math.PI / 2 };
    const id = await startMission(daemon.url, { waypoints: [goal] });
    const running = await waitFor(() => mission(daemon.url, id), (m) => m.path.length >= 2, 5000, 'a path');
    assert.equal(running.status, 'active');
    assert.ok(running.eta_s > 0);
    const done = await waitFor(() => mission(daemon.url, id), (m) => m.status !== 'active', 30000, 'the end');
    assert.equal(done.status, 'succeeded', done.error);
    assert.equal(done.progress, 1);
    await sleep(100);  // one state push: the robot is idle as soon as the mission ends
    const s = await state(daemon.url);
    const truth = s.sim_true_pose;
    const error_cm = Math.hypot(truth.x - goal.x, truth.y - goal.y) * 100;
    const error_deg = Math.abs(degrees(angleDiff(truth.yaw, goal.yaw)));
    assert.ok(error_cm <= 2.0, `${error_cm.toFixed(2)} cm from the goal`);
    assert.ok(error_deg <= 2.0, `${error_deg.toFixed(2)} degrees from the goal heading`);
    assert.equal(s.mode, 'idle');
    const listed = await getJson(`${daemon.url}/api/v1/missions`);
    api.check('Missions', listed.body);
    assert.ok(listed.body.missions.some((m) => m.id === id && m.status === 'succeeded'), 'persisted');
  });

  test('a paused mission stays still, resumes and finishes', async () => {
    const id = await startMission(daemon.url, { waypoints: [{ x: 1.0, y: 0.75 }], speed_limit_mps: 0.3 });
    await waitFor(() => state(daemon.url), (s) => s.velocity.linear_mps > 0.1, 8000, 'the robot moving');
    const paused = await postJson(`${daemon.url}/api/v1/missions/${id}/pause`, {});
    assert.equal(paused.status, 200);
    assert.equal(paused.body.status, 'paused');
    assert.equal((await postJson(`${daemon.url}/api/v1/missions/${id}/pause`, {})).status, 409);
    await sleep(800);  // braking
    const held = (await state(daemon.url)).sim_true_pose;
    await sleep(1500);
    const still = (await state(daemon.url)).sim_true_pose;
    assert.ok(Math.hypot(still.x - held.x, still.y - held.y) < 0.002, 'stays still while paused');
    assert.equal((await postJson(`${daemon.url}/api/v1/missions/${id}/resume`, {})).body.status, 'active');
    const done = await waitFor(() => mission(daemon.url, id), (m) => m.status !== 'active', 30000, 'the end');
    assert.equal(done.status, 'succeeded', done.error);
    assert.equal((await postJson(`${daemon.url}/api/v1/missions/${id}/cancel`, {})).status, 409);
    assert.equal((await postJson(`${daemon.url}/api/v1/missions/nope/cancel`, {})).status, 404);
  });

  test('a named place is a goal', async () => {
    const created = await postJson(`${daemon.url}/api/v1/places`, { name: 'dock', x: 2.5, y: 0.7, yaw: 0 });
    assert.equal(created.status, 201);
    api.check('Place', created.body);
    assert.equal((await postJson(`${daemon.url}/api/v1/places`, { name: 'dock', x: 1, y: 1 })).status, 409);
    // Issue 36: a place the robot cannot stand at (on the wall between the rooms, off the map) is refused, saying why.
    for (const [where, why] of [[{ x: 3.0, y: 1.5 }, /wall|too close/], [{ x: 100, y: 100 }, /outside the map/]]) {
      const refused = await postJson(`${daemon.url}/api/v1/places`, { name: 'nowhere', ...where });
      assert.equal(refused.status, 422, JSON.stringify(refused.body));
      assert.match(refused.body.detail, why);
    }
    assert.ok(!(await getJson(`${daemon.url}/api/v1/places`)).body.places.some((p) => p.name === 'nowhere'));
    const id = await startMission(daemon.url, { waypoints: [{ place: 'dock' }] });
    const done = await waitFor(() => mission(daemon.url, id), (m) => m.status !== 'active', 30000, 'the end');
    assert.equal(done.status, 'succeeded', done.error);
    assert.equal(done.waypoints[0].place, 'dock');
  });

  test('a keep-out zone across the only doorway: a clear error and no motion', async () => {
    const zone = await postJson(`${daemon.url}/api/v1/zones`, { name: 'wet floor', kind: 'keep_out', polygon: doorway });
    assert.equal(zone.status, 201);
    api.check('Zone', zone.body);
    try {
      const plan = await postJson(`${daemon.url}/api/v1/plan`, { goal: upperRoom });
      assert.equal(plan.status, 422);
      assert.equal(plan.body.code, 'no_path');
      const before = (await state(daemon.url)).sim_true_pose;
      const id = await startMission(daemon.url, { waypoints: [upperRoom] });
      const failed = await waitFor(() => mission(daemon.url, id), (m) => m.status !== 'active', 5000, 'failure');
      assert.equal(failed.status, 'failed');
      assert.match(failed.error, /no path/);
      await sleep(500);
      const after = (await state(daemon.url)).sim_true_pose;
      assert.ok(Math.hypot(after.x - before.x, after.y - before.y) < 0.005, 'no motion');
      // A goal inside the zone is refused up front.
      const inside = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 1.4, y: 1.5 }] });
      assert.equal(inside.status, 422);
      assert.match(inside.body.detail, /keep-out/);
    } finally {
      assert.equal((await sendJson('DELETE', `${daemon.url}/api/v1/zones/${zone.body.id}`)).status, 204);
    }
    assert.equal((await postJson(`${daemon.url}/api/v1/plan`, { goal: upperRoom })).status, 200);
  });

  test('a zone drawn across the path during a mission is respected at once', async () => {
    const id = await startMission(daemon.url, { waypoints: [upperRoom], speed_limit_mps: 0.25 });
    await waitFor(() => state(daemon.url), (s) => s.velocity.linear_mps > 0.1, 8000, 'the robot moving');
    const zone = await postJson(`${daemon.url}/api/v1/zones`, { name: 'closed', kind: 'keep_out', polygon: doorway });
    try {
      const m = await waitFor(() => mission(daemon.url, id), (x) => x.status !== 'active', 8000, 'the mission to stop');
      assert.equal(m.status, 'failed');
      await sleep(1000);
      const s = await state(daemon.url);
      assert.ok(s.sim_true_pose.y < 1.2, `stopped before the zone, at y = ${s.sim_true_pose.y}`);
      assert.equal(s.velocity.linear_mps, 0);
    } finally {
      await sendJson('DELETE', `${daemon.url}/api/v1/zones/${zone.body.id}`);
    }
  });

  test('zones are validated', async () => {
    const cases = [
      { kind: 'keep_out', polygon: [[0, 0], [1, 0]] },
      { kind: 'speed_limit', polygon: [[0, 0], [1, 0], [1, 1]] },
      { kind: 'sideways', polygon: [[0, 0], [1, 0], [1, 1]] },
      { kind: 'keep_out', polygon: [[0, 0], [1, 'a'], [1, 1]] },
    ];
    for (const body of cases) {
      const res = await postJson(`${daemon.url}/api/v1/zones`, body);
      assert.equal(res.status, 400, JSON.stringify(body));
      api.check('Problem', res.body);
    }
    assert.equal((await getJson(`${daemon.url}/api/v1/zones/none`)).status, 404);
    const zones = await getJson(`${daemon.url}/api/v1/zones`);
    api.check('Zones', zones.body);
    assert.equal(zones.body.zones.length, 0);
  });
});

describe('what the robot is told survives a restart', () => {
  const stateDir = mkdtempSync(join(tmpdir(), 'corridor-restart-'));
  after(() => rmSync(stateDir, { recursive: true, force: true }));

  test('zones, places and map edits are kept, atomically saved', async () => {
    const first = await startDaemon({ config, stateDir });
    let zoneId;
    try {
      zoneId = (await postJson(`${first.url}/api/v1/zones`,
        { name: 'slow', kind: 'speed_limit', max_speed_mps: 0.2, polygon: [[2.5, 0.2], [3.5, 0.2], [3.5, 1.2], [2.5, 1.2]] })).body.id;
      await postJson(`${first.url}/api/v1/places`, { name: 'charger', x: 3.5, y: 2.5, yaw: 1.57 });
      // Wall up the doorway on the map itself: row 30 is y = 1.5 .. 1.55; columns 16 to 40 span x = 0.8 .. 2.05.
      const edit = await sendJson('PUT', `${first.url}/api/v1/map/cells`,
        { rects: [{ x0: 16, y0: 29, x1: 40, y1: 31, value: 100 }] });
      assert.equal(edit.status, 200, JSON.stringify(edit.body));
      assert.equal(edit.body.changed, 25 * 3);
      assert.equal((await postJson(`${first.url}/api/v1/plan`, { goal: upperRoom })).body.code, 'no_path');
      const bad = await sendJson('PUT', `${first.url}/api/v1/map/cells`, { cells: [[5, 5, 0], [500, 5, 100]] });
      assert.equal(bad.status, 422);
      assert.match(bad.body.detail, /cells\[1\]/);
      assert.equal((await sendJson('PUT', `${first.url}/api/v1/map/cells`, { cells: [[5, 5, 7]] })).status, 422);
    } finally {
      await first.stop();
    }
    const second = await startDaemon({ config, stateDir });
    try {
      const zones = (await getJson(`${second.url}/api/v1/zones`)).body.zones;
      assert.deepEqual(zones.map((z) => [z.id, z.kind, z.max_speed_mps]), [[zoneId, 'speed_limit', 0.2]]);
      const places = (await getJson(`${second.url}/api/v1/places`)).body.places;
      assert.equal(places[0].name, 'charger');
      const walled = await postJson(`${second.url}/api/v1/plan`, { goal: upperRoom });
      assert.equal(walled.body.code, 'no_path', JSON.stringify(walled.body) + second.log());
      const plan = await postJson(`${second.url}/api/v1/plan`, { goal: { x: 3.2, y: 0.7 } });
      assert.equal(plan.status, 200);
      assert.ok(plan.body.path.some((p) => Math.abs(p.speed_limit_mps - 0.2) < 1e-6), 'the speed zone is on the path');
      const maps = await getJson(`${second.url}/api/v1/maps`);
      api.check('Maps', maps.body);
      assert.equal(maps.body.active, 'lse_arena');
    } finally {
      await second.stop();
    }
  });

  test('another map can be selected; its zones are its own', async () => {
    // A second map, copied into the state directory as a user would.
    mkdirSync(join(stateDir, 'maps', 'original'), { recursive: true });
    for (const f of ['lse_arena.yaml', 'lse_arena.pgm']) {
      copyFileSync(join(sourceDir, 'tests/data/maps/lse_arena', f), join(stateDir, 'maps', 'original', f));
    }
    copyFileSync(join(stateDir, 'maps', 'original', 'lse_arena.yaml'), join(stateDir, 'maps', 'original', 'map.yaml'));
    const daemon = await startDaemon({ config, stateDir });
    try {
      const maps = (await getJson(`${daemon.url}/api/v1/maps`)).body;
      assert.deepEqual(maps.maps, ['lse_arena', 'original']);
      const id = (await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 3.0, y: 0.7 }] })).body.id;
      const busy = await sendJson('PUT', `${daemon.url}/api/v1/map/active`, { name: 'original' });
      assert.equal(busy.status, 409);
      assert.equal(busy.body.code, 'mission_in_progress');
      await postJson(`${daemon.url}/api/v1/missions/${id}/cancel`, {});
      const selected = await sendJson('PUT', `${daemon.url}/api/v1/map/active`, { name: 'original' });
      assert.equal(selected.status, 200, JSON.stringify(selected.body));
      const map = (await getJson(`${daemon.url}/api/v1/map`)).body;
      assert.equal(map.name, 'original');
      assert.equal((await getJson(`${daemon.url}/api/v1/state`)).body.map.name, 'original');
      // The unedited original has its doorway open, and the first map's zones stay with the first map.
      assert.equal((await postJson(`${daemon.url}/api/v1/plan`, { goal: upperRoom })).status, 200);
      assert.deepEqual((await getJson(`${daemon.url}/api/v1/zones`)).body.zones, []);
      assert.equal((await sendJson('PUT', `${daemon.url}/api/v1/map/active`, { name: 'nope' })).status, 422);
      assert.equal((await sendJson('PUT', `${daemon.url}/api/v1/map/active`, { name: '../etc' })).status, 422);
    } finally {
      await daemon.stop();
    }
  });
});
