// The detection hook in corridord with the simulator: the simulated person in the camera's view is detected and located,
// the face looks at them and greets them, the robot slows near them, and detections pushed in by an external detector
// are merged until their ttl; bad pushes get a problem.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  getJson, launchBrowser, openApiValidator, openConsole, postJson, sendJson, sleep, startDaemon, waitFor, writeRoom,
} from './daemon.mjs';

const api = openApiValidator();
const dir = mkdtempSync(join(tmpdir(), 'corridor-perception-'));
const room = writeRoom(dir, 10, 6);
after(() => rmSync(dir, { recursive: true, force: true }));

const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;
const detections = async (url) => {
  const res = await getJson(`${url}/api/v1/detections`);
  assert.equal(res.status, 200);
  api.check('Detections', res.body);
  return res.body.detections;
};

// Where a world point lies in the robot's base frame.
function inBase(robot, p) {
  const dx = p.x - robot.x;
  const dy = p.y - robot.y;
  const c = Math.cos(robot.yaw);
  const s = Math.sin(robot.yaw);
  return { x: c * dx + s * dy, y: -s * dx + c * dy };
}

describe('people in the camera', () => {
  let daemon;
  let person;
  before(async () => {
    // One person standing still somewhere near the robot's start in an empty room; the pose is the simulator's truth,
    // so that carrying the robot about does not make it lost.
    daemon = await startDaemon({ config: `
sim:
  world: "${room}"
  start: {x_m: 1.5, y_m: 3.0, yaw_deg: 0}
  pedestrians: 1
  pedestrians_within_m: 4
  crowd: {preferred_speed_mps: 0, max_speed_mps: 0}
localization: {source: sim_truth}
` });
    person = (await waitFor(() => state(daemon.url), (s) => s.sim_pedestrians.length === 1, 5000, 'the person'))
      .sim_pedestrians[0];
  });
  after(async () => { await daemon?.stop(); });

  // Carries the robot to `distance` metres from the person, on the side of the room's middle, facing them.
  async function faceThePerson(distance) {
    const toMiddle = Math.atan2(3.0 - person.y, 5.0 - person.x);
    const robot = { x: person.x + distance * Math.cos(toMiddle), y: person.y + distance * Math.sin(toMiddle),
      yaw: toMiddle + Math.PI };
    const res = await sendJson('PUT', `${daemon.url}/api/v1/sim/pose`, robot);
    assert.equal(res.status, 200, JSON.stringify(res.body));
    await waitFor(() => state(daemon.url), (s) => Math.hypot(s.sim_true_pose.x - robot.x, s.sim_true_pose.y - robot.y) < 0.05,
      3000, 'the robot carried');
    return robot;
  }

  test('a person in view is detected where they stand, tracked, and the face looks at them', async () => {
    const robot = await faceThePerson(2.5);
    const expected = inBase(robot, person);
    // The near surface of the body: its centre less the crowd's radius (0.25 m). Detections made from frames before
    // the robot was carried may still be the latest for a moment (more of them on a busy machine): the test waits for
    // one from where the robot now stands, not for the first one.
    const error = (x) => Math.hypot(x.position.x - (expected.x - 0.25), x.position.y - expected.y);
    const person_ = (d) => d.find((x) => x.class === 'person');
    const seen = await waitFor(() => detections(daemon.url), (d) => person_(d) && error(person_(d)) < 0.2, 5000,
      `the person detected where they stand, ${JSON.stringify(expected)}`);
    const found = person_(seen);
    assert.equal(found.source, 'sim');
    assert.ok(found.track_id > 0);
    const later = await waitFor(() => detections(daemon.url), (d) => d.some((x) => x.class === 'person'), 3000,
      'the person again');
    assert.equal(later.find((x) => x.class === 'person').track_id, found.track_id);
    const face = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/face`)).body, (f) => f.gaze_at_person,
      2000, 'the eyes on the person');
    api.check('Face', face);
    assert.ok(Math.abs(face.gaze - Math.atan2(expected.y, expected.x)) < 0.15, JSON.stringify(face));
  });

  test('standing in front of the idle robot, the person is greeted; driving at them, it slows to half speed', async () => {
    await faceThePerson(1.3);
    const greeted = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/face`)).body,
      (f) => f.said_kind === 'greeting', 5000, 'a greeting');
    assert.equal(greeted.said, 'Hello!');
    assert.equal(greeted.expression, 'happy');
    let slowed;
    for (let i = 0; i < 15 && !slowed; ++i) {
      await postJson(`${daemon.url}/api/v1/teleop`, { linear_mps: 0.5, angular_rps: 0 });
      await sleep(50);
      const s = await state(daemon.url);
      if (s.stop_reason === 'slowed near a person ahead') slowed = s;
    }
    assert.ok(slowed, 'never slowed for the person');
    assert.ok(slowed.command.linear_mps <= 0.25 + 1e-9, JSON.stringify(slowed.command));
    await postJson(`${daemon.url}/api/v1/teleop`, { linear_mps: 0, angular_rps: 0 });
  });

  test('detections pushed in by another detector are merged until their ttl', async () => {
    const res = await postJson(`${daemon.url}/api/v1/detections`, { source: 'phone', ttl_s: 1.0, detections: [
      { class: 'person', score: 0.8, position: { x: 2.0, y: -1.0, z: 0.9 } },
      { class: 'dog', box: { x: 10, y: 20, w: 30, h: 40 } }] });
    assert.equal(res.status, 202, JSON.stringify(res.body));
    api.check('DetectionsAccepted', res.body);
    assert.equal(res.body.accepted, 2);
    const merged = await waitFor(() => detections(daemon.url), (d) => d.some((x) => x.source === 'phone'), 2000,
      'the pushed detections');
    const dog = merged.find((x) => x.class === 'dog');
    assert.deepEqual(dog.box, { x: 10, y: 20, w: 30, h: 40 });
    const pushed = merged.find((x) => x.source === 'phone' && x.class === 'person');
    assert.ok(Math.abs(pushed.bearing - Math.atan2(-1.0, 2.0)) < 1e-6);
    await waitFor(() => detections(daemon.url), (d) => !d.some((x) => x.source === 'phone'), 3000, 'their expiry');
  });

  test('the console draws what the robot sees: boxes over the camera view, people on the map', async () => {
    const browser = await launchBrowser();
    try {
      const { page, errors } = await openConsole(browser, daemon.url);
      await page.waitForFunction(() => {
        const img = document.querySelector('[data-testid=camera]');
        return img instanceof HTMLImageElement && img.complete && img.naturalWidth > 0;
      }, null, { timeout: 15000 });
      const res = await postJson(`${daemon.url}/api/v1/detections`, { source: 'tablet', ttl_s: 8, detections: [
        { class: 'person', score: 0.9, box: { x: 40, y: 30, w: 60, h: 160 }, position: { x: 2.5, y: 0.5, z: 0.9 } }] });
      assert.equal(res.status, 202, JSON.stringify(res.body));
      await page.getByTestId('detections').filter({ hasText: /person \d+ at 2\.5 m/ }).waitFor({ timeout: 5000 });
      await page.waitForSelector('path.detected-person', { timeout: 5000 });
      // The box's edge, in the overlay's purple, where the box's top-left corner falls on the shown image.
      const purple = await page.evaluate(() => {
        const img = document.querySelector('[data-testid=camera]');
        const canvas = document.querySelector('[data-testid=detections-overlay]');
        const sx = canvas.width / img.naturalWidth;
        const sy = canvas.height / img.naturalHeight;
        const [r, g, b, a] = canvas.getContext('2d').getImageData(Math.round(40 * sx), Math.round(110 * sy), 1, 1).data;
        return a > 0 && r > 120 && b > 200 && g < 150;
      });
      assert.ok(purple, 'the box is drawn over the camera view');
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });

  test('bad pushes get a problem and change nothing', async () => {
    for (const body of [{}, { source: 'x y', detections: [] }, { source: 'a', detections: 'no' },
      { source: 'a', ttl_s: 0, detections: [] }, { source: 'a', ttl_s: 1000, detections: [] },
      { source: 'a', detections: [{ score: 0.5 }] }, { source: 'a', detections: [{ class: 'person', score: 2 }] },
      { source: 'a', detections: [{ class: 'person', box: { x: 0, y: 0, w: -1, h: 5 } }] },
      { source: 'a', detections: [{ class: 'person', position: { x: 'far', y: 0 } }] },
      { source: 'a', detections: Array(101).fill({ class: 'person' }) }, { source: 'a', detections: [], extra: 1 }]) {
      const res = await postJson(`${daemon.url}/api/v1/detections`, body);
      assert.equal(res.status, 400, JSON.stringify(body));
      assert.equal(res.type, 'application/problem+json');
      api.check('Problem', res.body);
    }
    assert.ok(!(await detections(daemon.url)).some((x) => x.source === 'a'));
  });
});
