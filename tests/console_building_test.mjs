// The console with a building in a real browser: the floor the robot is on in the header, the lift's door, car and
// lobby and the map's doors drawn on the map, and the floor picker sending the robot to a place on another floor
// (the mission the daemon makes of it rides the lift); drawing a door and a lift's stop with their tools.
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { apiFetch, getJson, gotoConsole, launchBrowser, postJson, startDaemon, waitFor, writeRoom } from './daemon.mjs';

let dir;
let daemon;
let browser;
let page;

// A 6 x 4 m room as map `name` in `dir` (the floors' maps need names of their own).
function floorMap(name) {
  const room = mkdtempSync(join(dir, `${name}-`));
  writeRoom(room, 6, 4);
  writeFileSync(join(dir, `${name}.pgm`), readFileSync(join(room, 'room.pgm')));
  writeFileSync(join(dir, `${name}.yaml`), readFileSync(join(room, 'room.yaml'), 'utf8').replace('room.pgm', `${name}.pgm`));
  return join(dir, `${name}.yaml`);
}

// Presses on the map at map-frame point `from`, drags to `to` and lets go (the whole room in view).
async function drag(from, to) {
  const point = ([x, y]) => page.evaluate(([px, py]) => {
    const { map } = window.corridorConsole.view;
    map.setView([2.0, 3.0], 6, { animate: false });
    const p = map.latLngToContainerPoint([py, px]);
    const box = map.getContainer().getBoundingClientRect();
    return { x: box.left + p.x, y: box.top + p.y };
  }, [x, y]);
  const a = await point(from);
  const b = await point(to);
  await page.mouse.move(a.x, a.y);
  await page.mouse.down();
  await page.mouse.move(b.x, b.y, { steps: 5 });
  await page.mouse.up();
}

async function put(path, body) {
  const res = await apiFetch(`${daemon.url}${path}`, {
    method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body) });
  assert.equal(res.status, 200, await res.text());
}

before(async () => {
  dir = mkdtempSync(join(tmpdir(), 'corridor-console-building-'));
  daemon = await startDaemon({ config: `
building:
  floors:
    - {name: L1, map: "${floorMap('ground')}"}
    - {name: L2, map: "${floorMap('first')}"}
  lifts:
    - id: lift1
      stops:
        - {floor: L1, x1_m: 4.3, y1_m: 1.3, x2_m: 4.3, y2_m: 2.7, lobby_x_m: 3.5, lobby_y_m: 2.0}
        - {floor: L2, x1_m: 4.3, y1_m: 1.3, x2_m: 4.3, y2_m: 2.7, lobby_x_m: 3.5, lobby_y_m: 2.0}
  controller:
    call: {url: "http://127.0.0.1:9/lifts/{lift}"}
localization: {source: mcl}
sim:
  start: {x_m: 1.0, y_m: 2.0, yaw_deg: 0}
  camera: {width: 160, height: 120}
  dock: {enabled: false}
  doors:
    - {id: d1, x1_m: 2.0, y1_m: 0.0, x2_m: 2.0, y2_m: 0.8, open: true}
` });
  // A place on L2: made while L2's map is the one in use, as an installer would.
  await put('/api/v1/map/active', { name: 'first' });
  assert.equal((await postJson(`${daemon.url}/api/v1/places`, { name: 'kitchen', x: 1.5, y: 1.0, yaw: 0 })).status, 201);
  await put('/api/v1/map/active', { name: 'ground' });
  browser = await launchBrowser();
  page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (e) => { throw e; });
  await gotoConsole(page, daemon.url);
  await page.waitForFunction(() => window.corridorConsole !== undefined);
});

after(async () => {
  await browser?.close();
  await daemon?.stop();
  if (dir) rmSync(dir, { recursive: true, force: true });
});

test('the floor, the lift and the doors are on the console', async () => {
  await page.getByTestId('floor').filter({ hasText: 'floor L1' }).waitFor();
  for (const marker of ['.lift-door', '.lift-car', '.lift-lobby', '.door.door-idle']) {
    await page.locator(marker).first().waitFor({ state: 'attached' });
    assert.equal(await page.locator(marker).count(), 1, marker);
  }
});

test('the floor picker sends the robot to a place on another floor, through the lift', async () => {
  await page.getByTestId('floor-select').selectOption('L2');
  await page.getByTestId('floor-place').selectOption('kitchen');
  await page.getByTestId('floor-go').click();
  const { body: state } = await waitFor(() => getJson(`${daemon.url}/api/v1/state`),
    (s) => s.body.mission?.status === 'active', 10000, 'the mission started');
  assert.deepEqual(state.mission.waypoints.map((w) => [w.action, w.floor]), [['ride_lift', 'L1'], ['go', 'L2']]);
  assert.equal(state.mission.waypoints[1].place, 'kitchen');
  assert.equal((await postJson(`${daemon.url}/api/v1/missions/${state.mission.id}/cancel`, {})).status, 200);
});

test('a door drawn with the Door tool is on the map and in the API, and can be removed', async () => {
  await page.getByRole('button', { name: 'Door', exact: true }).click();
  page.once('dialog', (d) => d.accept('d2'));
  await drag([3.0, 0.2], [3.0, 1.2]);
  await page.getByTestId('message').filter({ hasText: "door 'd2' added" }).waitFor();
  await waitFor(() => page.locator('.door').count(), (n) => n === 2, 5000, 'two doors drawn');
  const { body } = await getJson(`${daemon.url}/api/v1/doors`);
  const drawn = body.doors.find((d) => d.id === 'd2');
  assert.equal(drawn.source, 'drawn');
  assert.ok(Math.abs(drawn.x1 - 3.0) < 0.05 && Math.abs(drawn.y2 - 1.2) < 0.05, JSON.stringify(drawn));
  assert.equal((await apiFetch(`${daemon.url}/api/v1/doors/d1`, { method: 'DELETE' })).status, 409);
  assert.equal((await apiFetch(`${daemon.url}/api/v1/doors/d2`, { method: 'DELETE' })).status, 204);
  await page.getByRole('button', { name: 'Pan' }).click();
});

test('an RMF fleet adapter that rode the lift itself localizes the robot on the other floor\'s map', async () => {
  const localize = (map, cmd) => postJson(`${daemon.url}/api/v1/rmf/localize`,
    { cmd_id: cmd, pose: [1.0, 2.0, 0.0], map_name: map });
  assert.equal((await localize('nowhere', 1)).status, 422);
  assert.equal((await localize('first', 2)).status, 200);
  let { body: state } = await getJson(`${daemon.url}/api/v1/state`);
  assert.equal(state.floor, 'L2');
  await page.getByTestId('floor').filter({ hasText: 'floor L2' }).waitFor();
  // navigate to a pose on another floor's map: through the lift.
  const nav = await postJson(`${daemon.url}/api/v1/rmf/navigate`,
    { cmd_id: 3, pose: [1.0, 1.0, 0.0], map_name: 'ground', speed_limit: 0.0 });
  assert.equal(nav.status, 201, JSON.stringify(nav.body));
  ({ body: state } = await getJson(`${daemon.url}/api/v1/state`));
  assert.deepEqual(state.mission.waypoints.map((w) => w.action), ['ride_lift', 'go']);
  assert.equal((await postJson(`${daemon.url}/api/v1/rmf/stop`, { cmd_id: 4 })).status, 200);
  assert.equal((await localize('ground', 5)).status, 200);
});

test('a lift stop drawn with its tool joins the building: its door, car and lobby on the map', async () => {
  await page.getByTestId('floor').filter({ hasText: 'floor L1' }).waitFor();
  await page.getByRole('button', { name: 'Lift stop' }).click();
  page.once('dialog', (d) => d.accept('west'));
  // Along the door from south to north at x = 0.6: the lobby 0.8 m to the east, facing west.
  await drag([0.6, 0.5], [0.6, 1.5]);
  await page.getByTestId('message').filter({ hasText: "lift 'west' stops on floor L1" }).waitFor();
  await waitFor(() => page.locator('.lift-door').count(), (n) => n === 2, 5000, 'two lift doors drawn');
  const { body } = await getJson(`${daemon.url}/api/v1/building`);
  const west = body.lifts.find((l) => l.id === 'west');
  assert.equal(west.stops.length, 1);
  assert.ok(Math.abs(west.stops[0].lobby.x - 1.4) < 0.05 && Math.abs(Math.abs(west.stops[0].lobby.yaw) - Math.PI) < 0.05,
    JSON.stringify(west.stops[0]));
  assert.equal((await apiFetch(`${daemon.url}/api/v1/building/lifts/west/stops/L1`, { method: 'DELETE' })).status, 204);
  await page.getByRole('button', { name: 'Pan' }).click();
});
