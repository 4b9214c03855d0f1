// Planning and missions over HTTP in a small real arena (lse_arena, 4 x 3 m): a lower room and two upper rooms joined
// by one 1.2 m doorway (x 0.8 to 2.0, y about 1.5). What the robot does with its missions (arriving within 2 cm, pausing,
// places, keep-out zones) is tests/missions_lockstep_test.cc in simulated time; here are the requests, their answers
// against the OpenAPI document, and what survives a restart.
import assert from 'node:assert/strict';
import { copyFileSync, mkdirSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import { getJson, openApiValidator, postJson, sendJson, sourceDir, startDaemon } from './daemon.mjs';

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

const state = async (url) => (await getJson(`${url}/api/v1/state`)).body;

describe('missions in the arena', () => {
  let daemon;
  before(async () => { daemon = await startDaemon({ config }); });
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

  test('a mission over REST is started, described and cancelled', async () => {
    const started = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [upperRoom] });
    assert.equal(started.status, 201, JSON.stringify(started.body));
    api.check('Mission', started.body);
    const described = await getJson(`${daemon.url}/api/v1/missions/${started.body.id}`);
    api.check('Mission', described.body);
    const cancelled = await postJson(`${daemon.url}/api/v1/missions/${started.body.id}/cancel`, {});
    assert.equal(cancelled.status, 200, JSON.stringify(cancelled.body));
    assert.equal(cancelled.body.status, 'canceled');
    const listed = await getJson(`${daemon.url}/api/v1/missions`);
    api.check('Missions', listed.body);
    assert.ok(listed.body.missions.some((m) => m.id === started.body.id));
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

describe('the map library over REST', () => {
  test('a map is imported, exported, renamed and deleted; its zones go with it', async () => {
    const stateDir = mkdtempSync(join(tmpdir(), 'corridor-maps-'));
    const daemon = await startDaemon({ config, stateDir });
    const url = `${daemon.url}/api/v1`;
    const arena = join(sourceDir, 'tests/data/maps/lse_arena');
    const yaml = readFileSync(join(arena, 'lse_arena.yaml'), 'utf8');
    const image = readFileSync(join(arena, 'lse_arena.pgm')).toString('base64');
    const zone = { name: 'slow', kind: 'speed_limit', max_speed_mps: 0.2, polygon: [[2.5, 0.2], [3.5, 0.2], [3.5, 1.2]] };
    try {
      // Imported map_server files join the library; the map in use stays in use.
      const imported = await postJson(`${url}/maps`, { name: 'annex', yaml, image });
      assert.equal(imported.status, 201, JSON.stringify(imported.body));
      api.check('Maps', imported.body);
      assert.deepEqual(imported.body, { maps: ['lse_arena', 'annex'], active: 'lse_arena' });
      const refused = async (body, status, code) => {
        const answer = await postJson(`${url}/maps`, body);
        assert.equal(answer.status, status, JSON.stringify(answer.body));
        if (code) assert.equal(answer.body.code, code);
        return answer.body.detail;
      };
      await refused({ name: 'annex', yaml, image }, 409, 'name_taken');
      await refused({ name: '../annex', yaml, image }, 422, 'invalid_name');
      assert.match(await refused({ name: 'b', yaml, image: 'bm90IGFuIGltYWdl' }, 422, 'invalid_map'), /image/);
      assert.match(await refused({ name: 'b', yaml: 'resolution: -1', image }, 422, 'invalid_map'), /map_server/);
      await refused({ name: 'b', yaml, image: '%%%' }, 400);
      await refused({ name: 'b', yaml }, 400);
      assert.deepEqual((await getJson(`${url}/maps`)).body.maps, ['lse_arena', 'annex'], 'nothing half-imported');

      // Exported as map_server files that import again into the same grid.
      const files = await getJson(`${url}/maps/annex/files`);
      assert.equal(files.status, 200);
      api.check('MapFiles', files.body);
      assert.match(files.body.yaml, /^image: annex\.png$/m);
      assert.equal(Buffer.from(files.body.image, 'base64').subarray(1, 4).toString(), 'PNG');
      const again = await postJson(`${url}/maps`, { name: 'annex-copy', yaml: files.body.yaml, image: files.body.image });
      assert.equal(again.status, 201, JSON.stringify(again.body));
      const copy = (await getJson(`${url}/maps/annex-copy/files`)).body;
      assert.equal(copy.image, files.body.image);

      // A zone drawn on the imported map goes with it through a rename; the map in use is not renamed or deleted.
      assert.equal((await sendJson('PUT', `${url}/map/active`, { name: 'annex' })).status, 200);
      assert.equal((await postJson(`${url}/zones`, zone)).status, 201);
      assert.equal((await sendJson('PATCH', `${url}/maps/annex`, { name: 'wing' })).body.code, 'map_in_use');
      assert.equal((await sendJson('DELETE', `${url}/maps/annex`)).body.code, 'map_in_use');
      assert.equal((await sendJson('DELETE', `${url}/maps/lse_arena`)).body.code, 'map_configured');
      assert.equal((await sendJson('PUT', `${url}/map/active`, { name: 'lse_arena' })).status, 200);
      const renamed = await sendJson('PATCH', `${url}/maps/annex`, { name: 'wing' });
      assert.equal(renamed.status, 200, JSON.stringify(renamed.body));
      assert.deepEqual(renamed.body.maps, ['lse_arena', 'annex-copy', 'wing']);
      assert.equal((await sendJson('PATCH', `${url}/maps/wing`, { name: 'annex-copy' })).body.code, 'name_taken');
      assert.equal((await sendJson('PATCH', `${url}/maps/nowhere`, { name: 'x' })).status, 404);
      assert.equal((await sendJson('PUT', `${url}/map/active`, { name: 'wing' })).status, 200);
      assert.deepEqual((await getJson(`${url}/zones`)).body.zones.map((z) => z.name), ['slow']);

      // Deleted with its zones: a map imported later under the name starts bare.
      assert.equal((await sendJson('PUT', `${url}/map/active`, { name: 'lse_arena' })).status, 200);
      assert.equal((await sendJson('DELETE', `${url}/maps/wing`)).status, 204);
      assert.equal((await getJson(`${url}/maps/wing/files`)).status, 404);
      assert.equal((await postJson(`${url}/maps`, { name: 'wing', yaml, image })).status, 201);
      assert.equal((await sendJson('PUT', `${url}/map/active`, { name: 'wing' })).status, 200);
      assert.deepEqual((await getJson(`${url}/zones`)).body.zones, []);
    } finally {
      await daemon.stop();
      rmSync(stateDir, { recursive: true, force: true });
    }
  });
});
