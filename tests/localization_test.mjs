// Localization in the daemon: Monte Carlo localization from the simulated laser in the default world (Willow
// Garage), checked against the simulator's ground truth: it follows a mission within centimetres, a kidnapped robot
// is noticed, its mission paused, and it is found again by a search of the map; an initial pose can be set. Without
// a laser, from the depth camera alone: it follows a mission, and a kidnapped robot turns on the spot to find itself.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  driveFor, getJson, openApiValidator, postJson, sendJson, sleep, startDaemon, waitFor,
} from './daemon.mjs';

const api = openApiValidator();
const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;
const localization = async (url) => (await getJson(`${url}/api/v1/localization`)).body;
const wrap = (a) => Math.atan2(Math.sin(a), Math.cos(a));
// How far the daemon's pose is from the simulator's truth: metres and degrees.
const errorOf = (s) => [Math.hypot(s.pose.x - s.sim_true_pose.x, s.pose.y - s.sim_true_pose.y),
  Math.abs(wrap(s.pose.yaw - s.sim_true_pose.yaw)) * 180 / Math.PI];
// Runs a mission through `waypoints` to its end, sampling the error to the truth: the last state and the worst
// [metres, degrees].
async function missionError(url, waypoints, ms) {
  const res = await postJson(`${url}/api/v1/missions`, { waypoints });
  assert.equal(res.status, 201, JSON.stringify(res.body));
  let worst = [0, 0];
  let s;
  const deadline = Date.now() + ms;
  do {
    s = await state(url);
    const [m, deg] = errorOf(s);
    worst = [Math.max(worst[0], m), Math.max(worst[1], deg)];
    assert.ok(Date.now() < deadline, `mission still ${s.mission?.status}`);
    await sleep(100);
  } while (s.mission?.status === 'active');
  return { s, worst };
}

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

  test('it localizes at the start and follows a mission within centimetres of the truth', async (t) => {
    const first = await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 10000, 'localization ok');
    api.check('Localization', first);
    assert.equal(first.source, 'mcl');
    assert.ok(first.particles.length > 0 && first.particle_count >= first.particles.length);
    const { s, worst } = await missionError(daemon.url,
      [{ x: 24.4, y: 26.5 }, { x: 25.0, y: 27.2 }, { x: 24.4, y: 24.6 }], 120000);
    t.diagnostic(`worst error during the mission: ${(100 * worst[0]).toFixed(1)} cm, ${worst[1].toFixed(2)} deg`);
    assert.equal(s.mission.status, 'succeeded', JSON.stringify(s.mission));
    assert.ok(worst[0] < 0.05 && worst[1] < 3, `worst ${worst}`);
  });

  test('a kidnapped robot is noticed, its mission paused, and found again by a search of the map', async (t) => {
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
    // The filter starts around the given pose and settles on the truth. Standing still it weighs its particles once
    // (then only after 5 cm or 0.05 rad of motion, as AMCL does), so turn on the spot for it, as a person would.
    await driveFor(daemon.url, { linear_mps: 0, angular_rps: 0.5 }, 1500);
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

  test('the robot stays where it stopped and localization starts there, without a search', async () => {
    let daemon = await startDaemon({ stateDir });
    let before;
    try {
      await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 10000, 'localization ok');
      // Carried off the start (a restart must not put it back there), then left standing.
      await kidnap(daemon.url, { x: 25.0, y: 27.2, yaw: 0.5 });
      await waitFor(async () => ({ l: await localization(daemon.url), s: await state(daemon.url) }),
        ({ l, s }) => l.health === 'ok' && errorOf(s)[0] < 0.05, 15000, 'relocalized');
      await sleep(500);
      before = await state(daemon.url);
    } finally {
      await daemon.stop();
    }
    daemon = await startDaemon({ stateDir });
    try {
      const l = await waitFor(() => localization(daemon.url), (x) => x.health === 'ok', 10000, 'localization ok after the restart')
        .catch((e) => { throw new Error(`${e.message}\n${daemon.log()}`); });
      const s = await state(daemon.url);
      assert.ok(Math.hypot(s.sim_true_pose.x - before.sim_true_pose.x, s.sim_true_pose.y - before.sim_true_pose.y) < 0.02,
        `the simulated robot moved: ${JSON.stringify([before.sim_true_pose, s.sim_true_pose])}`);
      assert.ok(errorOf(s)[0] < 0.05, `localized ${errorOf(s)[0]} m off`);
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
  });
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
sim:
  world: "${new URL('../config/worlds/willow_garage/willow-full-0.05.yaml', import.meta.url).pathname}"
  start: {x_m: 24.38, y_m: 24.07, yaw_deg: 90}
  laser: {enabled: false}
localization: {source: mcl}
` });
  });
  after(async () => { await daemon?.stop(); });

  test('it follows a mission from the camera\'s depth scans within centimetres of the truth', async (t) => {
    const first = await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 10000, 'localization ok');
    api.check('Localization', first);
    assert.equal(first.sensor, 'depth');
    const { s, worst } = await missionError(daemon.url, [{ x: 24.4, y: 26.5 }, { x: 25.0, y: 27.2 }], 90000);
    t.diagnostic(`worst error during the mission: ${(100 * worst[0]).toFixed(1)} cm, ${worst[1].toFixed(2)} deg`);
    assert.equal(s.mission.status, 'succeeded', JSON.stringify(s.mission));
    assert.ok(worst[0] < 0.1 && worst[1] < 4, `worst ${worst}`);
  });

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
