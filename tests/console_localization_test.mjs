// The console's localization and mapping in a real browser against a real corridord in the lse_arena: the filter's
// particles and ellipse on the map, the health, setting a pose by press-and-drag, relocalizing, mapping a new map
// (the map view shows it growing, then the saved map), and the 3D map's view.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { getJson, gotoConsole, launchBrowser, showMap, sourceDir, startDaemon } from './daemon.mjs';

const artifacts = process.env.CORRIDOR_ARTIFACTS ?? join(sourceDir, 'tests/artifacts');
const config = `
map: {file: "${sourceDir}tests/data/maps/lse_arena/lse_arena.yaml"}
sim:
  world: "${sourceDir}tests/data/maps/lse_arena/lse_arena.yaml"
  start: {x_m: 1.0, y_m: 0.75, yaw_deg: 0}
  camera: {rate_hz: 15, width: 160, height: 120}
localization: {source: mcl}
`;

let daemon;
let browser;
let page;
const errors = [];

before(async () => {
  daemon = await startDaemon({ config });
  browser = await launchBrowser();
  page = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  page.on('pageerror', (e) => errors.push(e.message));
  await gotoConsole(page, daemon.url);
  await page.waitForFunction(() => window.corridorConsole?.localization !== undefined);
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

test('the health, the particles and their ellipse; a pose set by press and drag; relocalize', async () => {
  await page.getByTestId('localization-health').filter({ hasText: /^ok$/ }).waitFor({ timeout: 15000 });
  await page.getByTestId('localization-detail').filter({ hasText: /laser · \d+ particles/ }).waitFor();
  await page.waitForFunction(() => document.querySelectorAll('path.particle').length > 50);
  await page.waitForSelector('path.localization-ellipse');

  // Press where the robot truly is and drag along its heading (+x): the daemon is told that pose.
  const truth = (await getJson(`${daemon.url}/api/v1/state`)).body.sim_true_pose;
  await page.getByRole('button', { name: 'Set pose' }).click();
  const from = await at(truth.x, truth.y);
  const to = await at(truth.x + 0.5, truth.y);
  const request = page.waitForRequest((r) => r.url().endsWith('/api/v1/localization/pose') && r.method() === 'PUT');
  const response = page.waitForResponse((r) => r.url().endsWith('/api/v1/localization/pose'));
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  for (let i = 1; i <= 10; ++i) await page.mouse.move(from.x + ((to.x - from.x) * i) / 10, from.y + ((to.y - from.y) * i) / 10);
  await page.mouse.up();
  const sent = JSON.parse((await request).postData());
  assert.ok(Math.hypot(sent.x - truth.x, sent.y - truth.y) < 0.05, JSON.stringify({ sent, truth }));
  assert.ok(Math.abs(sent.yaw) < 0.05, `yaw ${sent.yaw}`);
  assert.equal((await response).status(), 202);
  // The reply says whether the scan fits the map there (it does: this is where the robot is), not in red.
  const said = page.getByTestId('message').filter({ hasText: /^pose x [\d.]+ m, y [\d.]+ m taken: the scan fits/ });
  await said.waitFor();
  assert.ok(!(await said.evaluate((e) => e.classList.contains('error'))), 'a pose that fits is reported as an error');
  await page.getByTestId('localization-health').filter({ hasText: /^ok$/ }).waitFor({ timeout: 15000 });
  const l = (await getJson(`${daemon.url}/api/v1/localization`)).body;
  assert.ok(Math.hypot(l.pose.x - truth.x, l.pose.y - truth.y) < 0.1, JSON.stringify(l.pose));

  await page.getByRole('button', { name: 'Pan' }).click();
  await page.getByTestId('relocalize').click();
  await page.getByTestId('message').filter({ hasText: 'searching the whole map' }).waitFor();
  await page.getByTestId('localization-health').filter({ hasText: /^ok$/ }).waitFor({ timeout: 15000 });
});

test('map a new map: the view shows it as it is built, then the saved map in use', async () => {
  await page.getByTestId('mapping-name').fill('arena-remapped');
  await page.getByTestId('mapping-start').click();
  await page.getByTestId('mapping-status').filter({ hasText: /^mapping 'arena-remapped'/ }).waitFor({ timeout: 5000 });
  await page.waitForSelector('#map-area.mapping');
  // The map being built replaces the map image.
  await page.waitForFunction(() => /\/api\/v1\/mapping\/image/.test(document.querySelector('img.map-image')?.src ?? ''),
    null, { timeout: 15000 });
  await page.getByTestId('mapping-stop').click();
  await page.getByTestId('mapping-status').filter({ hasText: "'arena-remapped' saved and in use" })
    .waitFor({ timeout: 20000 });
  await page.locator('#map-name').filter({ hasText: 'arena-remapped' }).waitFor({ timeout: 5000 });
  await page.waitForFunction(() => /\/api\/v1\/map\/image/.test(document.querySelector('img.map-image')?.src ?? ''));
  assert.equal(await page.locator('#map-area.mapping').count(), 0);
  assert.ok((await getJson(`${daemon.url}/api/v1/maps`)).body.maps.includes('arena-remapped'));
});

test('the 3D map: opened, it draws the octree\'s voxels', async () => {
  await page.getByTestId('octomap-panel').locator('summary').click();
  await page.getByTestId('octomap-status').filter({ hasText: /\d+ occupied voxels of 5 cm/ }).waitFor({ timeout: 15000 });
  await page.waitForFunction(() => Number(document.querySelector('[data-testid=octomap-view]')?.dataset.voxels) > 0,
    null, { timeout: 10000 });
  await page.waitForSelector('[data-testid=octomap-view] canvas');
  mkdirSync(artifacts, { recursive: true });
  await page.screenshot({ path: join(artifacts, 'console-localization.png') });
  assert.deepEqual(errors, []);
});
