// Mapping from the daemon over real HTTP: started and stopped through the API, bad requests refused. The 3D map: a
// table the laser passes under is seen by the depth camera, the planner goes round it, and its octree is saved beside
// the map. A map built while a mission drives round the small house, its walls against the house's reference map, and
// exploring two rooms until no frontier is left are tested in simulated time: tests/mapping_lockstep_test.cc.
import assert from 'node:assert/strict';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  apiFetch, getJson, openApiValidator, postJson, startDaemon, waitFor,
} from './daemon.mjs';

const api = openApiValidator();
const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;
const localization = async (url) => (await getJson(`${url}/api/v1/localization`)).body;

describe('mapping the small house', () => {
  let daemon;
  const houseDir = new URL('../config/worlds/small_house/', import.meta.url).pathname;
  before(async () => {
    daemon = await startDaemon({ config: `
map: {file: "${houseDir}maps/map.yaml"}
sim:
  world: "${houseDir}worlds/small_house.world"
  start: {x_m: -3.5, y_m: 1.0, yaw_deg: 270}
localization: {source: mcl}
` });
  });
  after(async () => { await daemon?.stop(); });

  test('mapping is started and stopped over HTTP; bad requests change nothing', async () => {
    await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 15000, 'localization ok');
    const mapping = async () => (await getJson(`${daemon.url}/api/v1/mapping`)).body;
    api.check('Mapping', await mapping());
    assert.equal((await postJson(`${daemon.url}/api/v1/mapping/start`, { name: '../etc' })).status, 400);
    assert.equal((await postJson(`${daemon.url}/api/v1/mapping/start`, {})).status, 400);
    const taken = await postJson(`${daemon.url}/api/v1/mapping/start`, { name: 'map' });
    assert.equal(taken.status, 409);
    api.check('Problem', taken.body);
    assert.equal(taken.body.code, 'map_exists');
    assert.equal((await postJson(`${daemon.url}/api/v1/mapping/stop`, {})).body.code, 'not_mapping');

    const started = await postJson(`${daemon.url}/api/v1/mapping/start`, { name: 'house-new' });
    assert.equal(started.status, 202, JSON.stringify(started.body));
    api.check('Mapping', await waitFor(mapping, (m) => m.active, 5000, 'mapping under way'));
    assert.equal((await postJson(`${daemon.url}/api/v1/mapping/start`, { name: 'other' })).body.code, 'already_mapping');
    const during = await waitFor(mapping, (m) => m.map !== null, 10000, 'the map as built so far');
    const image = await apiFetch(`${daemon.url}${during.map.image_url}`);
    assert.equal(image.status, 200);
    assert.equal(image.headers.get('content-type'), 'image/png');
    assert.equal((await postJson(`${daemon.url}/api/v1/mapping/stop`, {})).status, 202);
    api.check('Mapping', await waitFor(mapping, (m) => !m.active, 20000, 'mapping over'));
  });
});

// One empty room 8 x 4 m with walls two cells thick, at 5 cm: the world and its map.
function writeLongRoom(dir) {
  const [w, h] = [164, 84];  // 8.2 x 4.2 m with the outer walls
  const pixels = Buffer.alloc(w * h, 254);
  for (let row = 0; row < h; ++row) {
    for (let col = 0; col < w; ++col) {
      if (col < 2 || col >= w - 2 || row < 2 || row >= h - 2) pixels[row * w + col] = 0;
    }
  }
  writeFileSync(join(dir, 'rooms.pgm'), Buffer.concat([Buffer.from(`P5\n${w} ${h}\n255\n`), pixels]));
  writeFileSync(join(dir, 'rooms.yaml'),
    'image: rooms.pgm\nresolution: 0.05\norigin: [-0.05, -0.05, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n');
  return join(dir, 'rooms.yaml');
}

describe('the 3D map', () => {
  const dir = mkdtempSync(join(tmpdir(), 'corridor-table-'));
  const room = writeLongRoom(dir);
  // A 1 m square table top 0.72 m high on four 4 cm legs, between the robot and the far end of the room: the laser
  // (0.2 m high) sees only the legs; the map does not have it.
  const table = { x: 3.8, y: 2.0, half: 0.5 };
  const config = (layer) => `
map: {file: "${room}"}
sim:
  world: "${room}"
  start: {x_m: 1.0, y_m: 2.0, yaw_deg: 0}
  obstacles:
    - {shape: table, x_m: ${table.x}, y_m: ${table.y}, size_m: ${table.half}, height_m: 0.72}
localization: {source: mcl}
octomap: {costmap_layer: ${layer}, update_every_s: 0.5}
`;
  const underTable = (p, margin) => Math.abs(p.x - table.x) < table.half + margin && Math.abs(p.y - table.y) < table.half + margin;
  // Whether a path (waypoints joined by straight legs) passes within `margin` of the table's footprint.
  const crossesTable = (path, margin) => path.slice(1).some((b, i) => {
    const a = path[i];
    const steps = Math.ceil(Math.hypot(b.x - a.x, b.y - a.y) / 0.02);
    for (let k = 0; k <= steps; ++k) {
      if (underTable({ x: a.x + ((b.x - a.x) * k) / steps, y: a.y + ((b.y - a.y) * k) / steps }, margin)) return true;
    }
    return false;
  });
  const planAcross = async (url) => {
    const res = await postJson(`${url}/api/v1/plan`, { goal: { x: 7.0, y: 2.0 } });
    assert.equal(res.status, 200, JSON.stringify(res.body));
    return res.body.path;
  };
  after(() => rmSync(dir, { recursive: true, force: true }));

  test('the table top is in the octree and the planner goes round it; the octree is saved beside the map', async (t) => {
    const stateDir = mkdtempSync(join(dir, 'state-'));
    let daemon = await startDaemon({ config: config(true), stateDir });
    try {
      await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 15000, 'localization ok');
      const octomap = async () => (await getJson(`${daemon.url}/api/v1/map/octomap`));
      const info = await waitFor(octomap, (r) => r.status === 200 && r.body.occupied > 0, 10000, 'an octree');
      api.check('Octomap', info.body);
      // The top's underside, seen from below: voxels above the table's footprint at its height.
      const voxels = new Float32Array(await (await apiFetch(`${daemon.url}${info.body.voxels_url}`)).arrayBuffer());
      let top = 0;
      for (let i = 0; i < voxels.length; i += 4) {
        if (underTable({ x: voxels[i], y: voxels[i + 1] }, 0) && voxels[i + 2] > 0.6 && voxels[i + 2] < 0.8) ++top;
      }
      t.diagnostic(`${voxels.length / 4} occupied voxels, ${top} of them the table top`);
      assert.ok(top >= 50, `${top} voxels of the table top`);
      // The planner has the layer once the octree saw the table: the path keeps its footprint and the robot's
      // radius clear.
      const path = await waitFor(() => planAcross(daemon.url), (p) => !crossesTable(p, 0.15), 10000,
        'a path round the table');
      t.diagnostic(`round the table: ${path.length} waypoints`);
      const bt = await apiFetch(`${daemon.url}${info.body.bt_url}`);
      assert.equal(bt.status, 200);
      assert.match(Buffer.from(await bt.arrayBuffer()).subarray(0, 40).toString('latin1'), /^# Octomap OcTree binary file/);
    } finally {
      await daemon.stop();
    }
    // Saved at shutdown in the map's folder (the configured map is named after its file), and read at the next start.
    const saved = join(stateDir, 'maps/rooms/map.bt');
    assert.ok(existsSync(saved), 'maps/rooms/map.bt');
    assert.match(readFileSync(saved).subarray(0, 40).toString('latin1'), /^# Octomap OcTree binary file/);
    daemon = await startDaemon({ config: config(true), stateDir });
    try {
      await waitFor(async () => daemon.log(), (log) => /octree: '.*map\.bt' read, \d+ leaves/.test(log), 5000, 'the octree read');
    } finally {
      await daemon.stop();
    }
  });

  test('without the layer the planner drives under the table (what the laser alone knows)', async () => {
    const daemon = await startDaemon({ config: config(false) });
    try {
      await waitFor(() => localization(daemon.url), (l) => l.health === 'ok', 15000, 'localization ok');
      await waitFor(async () => (await getJson(`${daemon.url}/api/v1/map/octomap`)).status, (s) => s === 200, 10000, 'an octree');
      assert.ok(crossesTable(await planAcross(daemon.url), 0), 'the straight path crosses the table');
    } finally {
      await daemon.stop();
    }
  });
});
