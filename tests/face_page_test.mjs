// The face kiosk page at /face in a real browser (Debian's chromium through playwright-core) against a real corridord in
// a small room: it renders on a small screen and a large one, shows each expression (a screenshot of each is a test
// artifact), is surprised when the robot bumps, looks toward a person pushed in as a detection, and shows that it is
// disconnected when the daemon goes away.
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { launchBrowser, postJson, sleep, sourceDir, startDaemon, writeRoom } from './daemon.mjs';

const artifacts = process.env.CORRIDOR_ARTIFACTS ?? join(sourceDir, 'tests/artifacts');
const dir = mkdtempSync(join(tmpdir(), 'corridor-face-'));
const room = writeRoom(dir, 10, 6);

let daemon;
let browser;
before(async () => {
  // The robot 0.6 m from the room's west wall, facing east: backing up bumps into it.
  daemon = await startDaemon({ config: `
sim:
  world: "${room}"
  start: {x_m: 0.6, y_m: 3.0, yaw_deg: 0}
localization: {source: sim_truth}
` });
  browser = await launchBrowser();
  mkdirSync(artifacts, { recursive: true });
});
after(async () => {
  await browser?.close();
  await daemon?.stop();
  rmSync(dir, { recursive: true, force: true });
});

const body = (page, key) => page.evaluate((k) => document.body.dataset[k], key);

test('the face page follows the robot: expressions, a bump, a person to look at, a lost connection', async (t) => {
  const page = await browser.newPage({ viewport: { width: 800, height: 480 } });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await page.goto(`${daemon.url}/face`);
  await page.waitForFunction(() => document.body.dataset.connected === 'true', null, { timeout: 10000 });
  assert.equal(await page.locator('#status').isHidden(), true);
  // No user yet: the robot's screen shows the setup code, the one the daemon wrote to its journal.
  const code = await page.getByTestId('setup-code').textContent();
  assert.match(daemon.log(), new RegExp(`setup code ${code}`));
  await postJson(`${daemon.url}/api/v1/users`, { username: 'face-admin', password: 'face-admin-password', role: 'admin' });
  await page.getByTestId('setup').waitFor({ state: 'hidden', timeout: 5000 });
  // The canvas fills the screen.
  const size = await page.evaluate(() => {
    const c = document.getElementById('face');
    return { w: c.clientWidth, h: c.clientHeight };
  });
  assert.deepEqual(size, { w: 800, h: 480 });

  // Every expression an app can ask for, one screenshot each.
  for (const expression of ['neutral', 'happy', 'focused', 'surprised', 'worried', 'sleepy', 'confused', 'sad']) {
    const res = await postJson(`${daemon.url}/api/v1/face`, { expression, hold_s: 2 });
    assert.equal(res.status, 202);
    // Eased in: the page has stopped moving to it.
    await page.waitForFunction((e) => document.body.dataset.expression === e && document.body.dataset.still === 'true',
      expression, { timeout: 3000 });
    await page.screenshot({ path: join(artifacts, `face-${expression}.png`) });
  }
  await page.setViewportSize({ width: 1920, height: 1080 });
  await page.waitForFunction(() => document.getElementById('face').width === Math.round(1920 * devicePixelRatio));
  await page.evaluate(() => new Promise((drawn) => requestAnimationFrame(() => requestAnimationFrame(drawn))));
  await page.screenshot({ path: join(artifacts, 'face-1080p.png') });
  // The last request's hold runs out: the face is the robot's own again.
  await page.waitForFunction(() => document.body.dataset.expression !== 'sad', null, { timeout: 5000 });

  // Backing into the wall it cannot see: surprised.
  let surprised = false;
  for (let i = 0; i < 60 && !surprised; ++i) {
    await postJson(`${daemon.url}/api/v1/teleop`, { linear_mps: -0.3, angular_rps: 0 });
    await sleep(100);
    surprised = (await body(page, 'expression')) === 'surprised';
  }
  assert.ok(surprised, 'the face never showed surprise at the bump');
  await postJson(`${daemon.url}/api/v1/teleop`, { linear_mps: 0, angular_rps: 0 });

  // A person pushed in ahead and to the robot's left: the eyes turn that way (to the viewer's right).
  const before = Number(await body(page, 'gaze'));
  const t0 = Date.now();
  const pushed = await postJson(`${daemon.url}/api/v1/detections`, { source: 'test', ttl_s: 3, detections: [
    { class: 'person', score: 0.9, position: { x: 1.5, y: 1.0, z: 0.9 } }] });
  assert.equal(pushed.status, 202);
  await page.waitForFunction(() => Number(document.body.dataset.gaze) > 0.3, null, { timeout: 3000 });
  t.diagnostic(`the eyes turned to the pushed person ${Date.now() - t0} ms after the push (gaze was ${before})`);
  await page.screenshot({ path: join(artifacts, 'face-looking-left.png') });

  // The daemon goes away: the page says so, and keeps trying.
  await daemon.stop();
  daemon = null;
  await page.waitForFunction(() => document.body.dataset.connected === 'false', null, { timeout: 5000 });
  assert.match(await page.locator('#status').textContent(), /disconnected/);
  await page.screenshot({ path: join(artifacts, 'face-disconnected.png') });
  assert.deepEqual(errors, []);
});
