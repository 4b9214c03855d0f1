// Localization in the real-time daemon: Monte Carlo localization from the simulated laser in the default world (Willow
// Garage), checked against the simulator's ground truth: a kidnapped robot is noticed, its mission paused, and it is
// found again by a search of the map; an initial pose can be set; the pose survives a restart. Without a laser, from
// the depth camera alone, a kidnapped robot turns on the spot to find itself. How closely localization follows a
// mission is measured in simulated time (tests/navigation_lockstep_test.cc), where the machine's load cannot decide it.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  driveUntil, getJson, loadMachine, openApiValidator, postJson, sendJson, startDaemon, waitFor,
} from './daemon.mjs';

const api = openApiValidator();
const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;
const localization = async (url) => (await getJson(`${url}/api/v1/localization`)).body;
const wrap = (a) => Math.atan2(Math.sin(a), Math.cos(a));
// How far the daemon's pose is from the simulator's truth: metres and degrees.
const errorOf = (s) => [Math.hypot(s.pose.x - s.sim_true_pose.x, s.pose.y - s.sim_true_pose.y),
  Math.abs(wrap(s.pose.yaw - s.sim_true_pose.yaw)) * 180 / Math.PI];
// Carries the simulated robot to `pose` and waits until the state shows it there (the simulator publishes its truth
// on its next step): before that, the old truth and the old estimate agree.
async function kidnap(url, pose) {
  const moved = await sendJson('PUT', `${url}/api/v1/sim/pose`, pose);
  assert.equal(moved.status, 200, JSON.stringify(moved.body));
  await waitFor(() => state(url), (s) => Math.hypot(s.sim_true_pose.x - pose.x, s.sim_true_pose.y - pose.y) < 0.01,
    2000, 'the simulator reports the robot where it was carried');
  return moved.body;
}

describe('localization from the laser in the default world', () => {
  let daemon;
  before(async () => { daemon = await startDaemon(); });
  after(async () => { await daemon?.stop(); });

  // How closely it follows a mission is measured in simulated time (tests/navigation_lockstep_test.cc): read over
  // HTTP from a real-time daemon, the estimate and the truth come from different moments, and a busy machine widened
  // the gap past what the test allowed (issue 36).
  test('a kidnapped robot is noticed, its mission paused, and found again by a search of the map', async (t) => {
    // Localized first: how well the scans fit when ok is what a sudden misfit is judged against.
    await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 20000, 'localization ok');
    api.check('SimPoseAccepted', await kidnap(daemon.url, { x: 25.0, y: 27.2, yaw: 0.5 }));
    // It believes it is still at the last goal; the mission's goal is 2 m from there.
    const res = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 24.4, y: 26.5 }] });
    assert.equal(res.status, 201, JSON.stringify(res.body));
    const t0 = Date.now();
    let confused = false;
    const found = await waitFor(async () => ({ l: await localization(daemon.url), s: await state(daemon.url) }),
      ({ l, s }) => {
        confused ||= s.face === 'confused';
        return l.health === 'ok' && errorOf(s)[0] < 0.2;
      }, 15000, 'relocalized');
    assert.ok(confused, 'the face was never confused while the robot was lost');
    const [m, deg] = errorOf(found.s);
    t.diagnostic(`found again ${Date.now() - t0} ms after the mission started, ${(100 * m).toFixed(1)} cm off`);
    assert.ok(deg < 5, `${deg} degrees off`);
    // Lost, the mission was paused (the robot stops); found, it went on.
    assert.match(daemon.log(), /localization lost: paused/);
    assert.match(daemon.log(), /found the robot at .* by a search of the whole map/);
    const done = await waitFor(() => state(daemon.url), (s) => s.mission?.status !== 'active' &&
      s.mission?.status !== 'paused', 60000, 'the mission resumed and over');
    assert.equal(done.mission.status, 'succeeded', JSON.stringify(done.mission));
  });

  test('an initial pose is taken, relocalization on request, and bad requests change nothing', async () => {
    const s = await state(daemon.url);
    const near = { x: s.sim_true_pose.x + 0.15, y: s.sim_true_pose.y - 0.1, yaw: wrap(s.sim_true_pose.yaw + 0.1) };
    const set = await sendJson('PUT', `${daemon.url}/api/v1/localization/pose`, { ...near, sigma_m: 0.3 });
    assert.equal(set.status, 202, JSON.stringify(set.body));
    api.check('LocalizationPoseAccepted', set.body);
    assert.equal(set.body.agrees, true, JSON.stringify(set.body));
    // The filter starts around the given pose and settles on the truth, the robot standing still.
    await waitFor(async () => ({ l: await localization(daemon.url), s: await state(daemon.url) }),
      ({ l, s: now }) => l.health === 'ok' && errorOf(now)[0] < 0.05, 15000, 'settled on the truth');
    const re = await postJson(`${daemon.url}/api/v1/localization/relocalize`, {});
    assert.equal(re.status, 202, JSON.stringify(re.body));
    await waitFor(async () => ({ l: await localization(daemon.url), s: await state(daemon.url) }),
      ({ l, s: now }) => l.health === 'ok' && errorOf(now)[0] < 0.05, 15000, 'relocalized on request');
    const off = await sendJson('PUT', `${daemon.url}/api/v1/localization/pose`, { x: 500, y: 0, yaw: 0 });
    assert.equal(off.status, 422);
    assert.equal(off.body.code, 'outside_map');
    for (const bad of [{ x: 24 }, { x: 24, y: 24, yaw: 'north' }, { x: 24, y: 24, yaw: 0, sigma_m: -1 }, [1, 2]]) {
      const r = await sendJson('PUT', `${daemon.url}/api/v1/localization/pose`, bad);
      assert.equal(r.status, 400, JSON.stringify(bad));
      api.check('Problem', r.body);
    }
    assert.equal((await sendJson('PUT', `${daemon.url}/api/v1/sim/pose`, { x: 500, y: 0, yaw: 0 })).status, 422);
    const after = await state(daemon.url);
    assert.ok(errorOf(after)[0] < 0.05, 'still where it was');
  });
});

describe('the pose across a restart', () => {
  const stateDir = mkdtempSync(join(tmpdir(), 'corridor-restart-'));
  after(() => rmSync(stateDir, { recursive: true, force: true }));

  // Issue 36: on a loaded machine a restart once came back at the configured start, 31 m from where the robot had
  // been found. Both daemons run here beside two busy threads, and the first stops as soon as the robot is found
  // and has been nudged a few centimetres (less than the distance that saves the pose while running).
  test('the robot stays where it stopped and localization starts there, without a search, under load', async () => {
    const unload = loadMachine(2);
    try {
      await restartsWhereItStopped();
    } finally {
      await unload();
    }
  });

  async function restartsWhereItStopped() {
    let daemon = await startDaemon({ stateDir });
    let before;
    try {
      await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 20000, 'localization ok');
      // Carried off the start (a restart must not put it back there), found again, then nudged.
      await kidnap(daemon.url, { x: 6.0, y: 6.0, yaw: 0.0 });
      assert.equal((await postJson(`${daemon.url}/api/v1/localization/relocalize`, {})).status, 202);
      await waitFor(async () => ({ l: await localization(daemon.url), s: await state(daemon.url) }),
        ({ l, s }) => l.health === 'ok' && errorOf(s)[0] < 0.05, 30000, 'relocalized');
      await driveUntil(daemon.url, { linear_mps: 0.1, angular_rps: 0 }, (x) => x.pose.x > 6.04, 5000,
        'nudged 4 cm forward');
      before = await waitFor(() => state(daemon.url), (s) => Math.abs(s.velocity?.linear_mps ?? 0) < 0.005 &&
        s.pose.x > 6.02, 10000, 'nudged forward and standing');
    } finally {
      await daemon.stop();
    }
    daemon = await startDaemon({ stateDir });
    try {
      const l = await waitFor(() => localization(daemon.url), (x) => x.health === 'ok', 20000, 'localization ok after the restart')
        .catch((e) => { throw new Error(`${e.message}\n${daemon.log()}`); });
      const s = await state(daemon.url);
      assert.ok(Math.hypot(s.sim_true_pose.x - before.sim_true_pose.x, s.sim_true_pose.y - before.sim_true_pose.y) < 0.02,
        `the simulated robot moved: ${JSON.stringify([before.sim_true_pose, s.sim_true_pose])}`);
      assert.ok(errorOf(s)[0] < 0.05, `localized ${errorOf(s)[0]} m off`);
      // Not merely found again: it started where it had stopped, nudge included.
      const restored = daemon.log().match(/starting where the robot was in map '[^']+': \(([-\d.]+), ([-\d.]+)\)/);
      assert.ok(restored, daemon.log());
      assert.ok(Math.hypot(restored[1] - before.pose.x, restored[2] - before.pose.y) < 0.02,
        `restored at (${restored[1]}, ${restored[2]}), stopped at ${JSON.stringify(before.pose)}`);
      assert.equal(l.source, 'mcl');
      assert.doesNotMatch(daemon.log(), /search of the whole map/);
      assert.match(daemon.log(), /starting where the robot was in map/);
    } finally {
      await daemon.stop();
    }
    // A damaged pose file is named in the log and the daemon starts anyway.
    writeFileSync(join(stateDir, 'pose.json'), '{"place": "willow-full-0.05", "x": ');
    daemon = await startDaemon({ stateDir });
    try {
      assert.equal((await getJson(`${daemon.url}/api/v1/health`)).status, 200);
      assert.match(daemon.log(), /pose.json: the saved pose cannot be read/);
    } finally {
      await daemon.stop();
    }
  }
});

describe('localization by odometry alone', () => {
  let daemon;
  before(async () => {
    daemon = await startDaemon({ config: `
sim:
  world: "${new URL('../config/worlds/willow_garage/willow-full-0.05.yaml', import.meta.url).pathname}"
  start: {x_m: 24.38, y_m: 24.07, yaw_deg: 90}
localization: {source: odometry}
` });
  });
  after(async () => { await daemon?.stop(); });

  test('it says so, and does not take a pose it cannot use', async () => {
    const l = await localization(daemon.url);
    api.check('Localization', l);
    assert.equal(l.source, 'odometry');
    const r = await sendJson('PUT', `${daemon.url}/api/v1/localization/pose`, { x: 24, y: 24, yaw: 0 });
    assert.equal(r.status, 409);
    assert.equal(r.body.code, 'not_localizing');
    assert.equal((await postJson(`${daemon.url}/api/v1/localization/relocalize`, {})).status, 409);
  });
});

describe('localization from the depth camera alone', () => {
  let daemon;
  before(async () => {
    daemon = await startDaemon({ config: `
devices: {laser: {driver: none}}
sim:
  world: "${new URL('../config/worlds/willow_garage/willow-full-0.05.yaml', import.meta.url).pathname}"
  start: {x_m: 24.38, y_m: 24.07, yaw_deg: 90}
localization: {source: mcl}
` });
  });
  after(async () => { await daemon?.stop(); });

  test('a kidnapped robot turns on the spot until it has seen enough, and is found again', async (t) => {
    await kidnap(daemon.url, { x: 24.4, y: 24.2, yaw: 2.5 });
    const t0 = Date.now();
    let confused = false;
    let turned = false;
    const found = await waitFor(async () => ({ l: await localization(daemon.url), s: await state(daemon.url) }),
      ({ l, s }) => {
        confused ||= s.face === 'confused';
        turned ||= l.look_around_rps > 0;
        return l.health !== 'lost' && errorOf(s)[0] < 0.2 && errorOf(s)[1] < 5;
      }, 15000, 'relocalized');
    t.diagnostic(`found again ${Date.now() - t0} ms after the kidnapping, ${(100 * errorOf(found.s)[0]).toFixed(1)} cm off`);
    assert.ok(confused, 'the face was never confused while the robot was lost');
    assert.ok(turned, 'the robot never turned to look around');
    assert.equal(found.l.look_around_rps, 0);
    assert.match(daemon.log(), /found the robot at .* by a search of the whole map/);
  });
});
