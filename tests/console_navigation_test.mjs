// The console's navigation tools in a real browser against a real corridord in the lse_arena: click a goal and see
// the plan, draw a no-go zone, and the robot's new path goes around it.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { getJson, gotoConsole, launchBrowser, showMap, sleep, sourceDir, startDaemon } from './daemon.mjs';

const artifacts = process.env.CORRIDOR_ARTIFACTS ?? join(sourceDir, 'tests/artifacts');
const config = `
sim:
  world: "${sourceDir}tests/data/maps/lse_arena/lse_arena.yaml"
  start: {x_m: 1.0, y_m: 0.75, yaw_deg: 0}
  camera: {rate_hz: 15, width: 160, height: 120}
  base: {odom_linear_noise: 0, odom_angular_noise: 0}
  obstacles:   # in the upper right room, off every path here: the console draws what the map does not show
    - {shape: box, x_m: 3.2, y_m: 2.5, size_m: 0.15, height_m: 0.5}
`;
// Across the straight line from the robot to the goal, leaving a gap of 0.75 m below it.
const zone = [[1.8, 0.8], [2.4, 0.8], [2.4, 1.6], [1.8, 1.6]];
const goal = { x: 3.2, y: 1.0 };

function inside(polygon, p) {
  let c = false;
  for (let i = 0, j = polygon.length - 1; i < polygon.length; j = i++) {
    const [xi, yi] = polygon[i];
    const [xj, yj] = polygon[j];
    if ((yi > p.y) !== (yj > p.y) && p.x < ((xj - xi) * (p.y - yi)) / (yj - yi) + xi) c = !c;
  }
  return c;
}

let daemon;
let browser;
let page;

before(async () => {
  daemon = await startDaemon({ config });
  browser = await launchBrowser();
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => { throw e; });
  await gotoConsole(page, daemon.url);
  await page.waitForFunction(() => window.corridorConsole !== undefined);
  await page.getByTestId('pose').filter({ hasText: 'x ' }).waitFor();  // the console has centred on the robot
  // Zoom so the whole arena fills the map, and let the page draw it.
  await showMap(page, [1.5, 2.0], 7);
});

after(async () => {
  await browser?.close();
  await daemon?.stop();
});

// The page coordinates of a map-frame point.
async function at(x, y) {
  return page.evaluate(([px, py]) => {
    const { map } = window.corridorConsole.view;
    const p = map.latLngToContainerPoint([py, px]);
    const box = map.getContainer().getBoundingClientRect();
    return { x: box.left + p.x, y: box.top + p.y };
  }, [x, y]);
}

async function clickAt(x, y) {
  const p = await at(x, y);
  await page.mouse.click(p.x, p.y);
}

test('click a goal: the plan is previewed, then driven', async () => {
  await page.getByRole('button', { name: 'Go to' }).click();
  await clickAt(goal.x, goal.y);
  const summary = page.getByTestId('plan-summary');
  await summary.filter({ hasText: /m, clearance/ }).waitFor({ timeout: 10000 });
  assert.equal(await page.locator('path.plan-preview').count(), 1);
  // Nothing moves until Go.
  const before = (await getJson(`${daemon.url}/api/v1/state`)).body;
  assert.notEqual(before.mode, 'mission');
  await page.getByRole('button', { name: 'Clear' }).click();
  assert.equal(await page.locator('path.plan-preview').count(), 0);
});

test('draw a no-go zone: the new path avoids it and the robot drives around it', async () => {
  await page.getByRole('button', { name: 'No-go zone' }).click();
  for (const [x, y] of zone) await clickAt(x, y);
  await clickAt(zone[0][0], zone[0][1]);  // closing click on the first corner
  await page.getByTestId('message').filter({ hasText: 'no-go zone added' }).waitFor({ timeout: 10000 });
  const zones = (await getJson(`${daemon.url}/api/v1/zones`)).body.zones;
  assert.equal(zones.length, 1);
  assert.equal(zones[0].kind, 'keep_out');
  // The same corners (Geoman may start the ring elsewhere), within a few centimetres of the clicks.
  assert.equal(zones[0].polygon.length, zone.length);
  for (const [x, y] of zone) {
    assert.ok(zones[0].polygon.some(([px, py]) => Math.hypot(px - x, py - y) < 0.05), `corner ${x}, ${y}`);
  }
  // Drawn once the console has fetched the zones again (after the message, on a busy machine).
  await page.waitForFunction(() => document.querySelectorAll('path.keep-out').length === 1, null, { timeout: 10000 });

  await page.getByRole('button', { name: 'Go to' }).click();
  await clickAt(goal.x, goal.y);
  await page.getByTestId('plan-summary').filter({ hasText: /m, clearance/ }).waitFor({ timeout: 10000 });
  await page.getByTestId('plan-go').click();
  await page.getByTestId('mission-status').filter({ hasText: 'active' }).waitFor({ timeout: 5000 });
  const seen = [];
  const end = Date.now() + 40000;
  let mission = null;
  while (Date.now() < end) {
    const s = (await getJson(`${daemon.url}/api/v1/state`)).body;
    seen.push(s.sim_true_pose);
    mission = s.mission;
    if (mission && mission.status !== 'active') break;
    await sleep(100);
  }
  assert.equal(mission?.status, 'succeeded', mission?.error);
  assert.ok(seen.length > 20);
  for (const p of seen) assert.ok(!inside(zones[0].polygon, p), `the robot entered the zone at ${p.x}, ${p.y}`);
  assert.ok(seen.some((p) => p.x > 1.8 && p.x < 2.4), 'it passed the zone');
  const last = seen.at(-1);
  assert.ok(Math.hypot(last.x - goal.x, last.y - goal.y) < 0.02);
  await page.getByTestId('mission-status').filter({ hasText: 'succeeded' }).waitFor({ timeout: 5000 });
  // The mission drove on the camera's frames: the console shows the loop's rate and frame-to-command latency.
  await page.getByTestId('control-loop').filter({ hasText: /Hz, frame to command .* ms \(p99/ }).waitFor({ timeout: 5000 });
  assert.equal(await page.locator('path.sim-obstacle').count(), 1);

  mkdirSync(artifacts, { recursive: true });
  await page.screenshot({ path: join(artifacts, 'console-navigation.png') });
});

test('paint a wall on the map: the map image changes and plans respect it', async () => {
  const revision = (await getJson(`${daemon.url}/api/v1/map`)).body.revision;
  await page.getByRole('button', { name: 'Wall' }).click();
  // A wall across the lower room's gap under the zone: from the outer wall up to the zone.
  const from = await at(2.1, 0.1);
  const to = await at(2.1, 0.9);
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  for (let i = 1; i <= 20; ++i) await page.mouse.move(from.x + ((to.x - from.x) * i) / 20, from.y + ((to.y - from.y) * i) / 20);
  await page.mouse.up();
  await page.getByTestId('message').filter({ hasText: 'map edited' }).waitFor({ timeout: 10000 });
  const map = (await getJson(`${daemon.url}/api/v1/map`)).body;
  assert.ok(map.revision > revision);
  await page.waitForFunction((r) => document.querySelector('img.map-image')?.src.includes(`revision=${r}`), map.revision);
  // Now the lower room is cut in two: the robot, east of the cut, cannot get back west.
  await page.getByRole('button', { name: 'Go to' }).click();
  await clickAt(1.0, 0.75);
  await page.getByTestId('plan-summary').filter({ hasText: /No path/ }).waitFor({ timeout: 10000 });
  assert.ok(await page.getByTestId('plan-go').isDisabled());
});
