// The Open-RMF robot contract under /api/v1/rmf/ over corridord's HTTP: what Open-RMF's fleet adapter template reads
// (position, battery, map), the robot's state against Open-RMF's own robot_state schema (tests/data/open_rmf_api,
// from open-rmf/rmf_api_msgs) while idle and while a navigate command drives, and bad calls answered with problems
// that start nothing. The commands carried out (navigate to completion, stop, dock and undock) are
// tests/rmf_lockstep_test.cc, in simulated time.
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import { getJson, openApiValidator, postJson, require, sourceDir, startDaemon, waitFor, writeRoom } from './daemon.mjs';

const api = openApiValidator();
const rmfSchema = (() => {
  const Ajv2020 = require('ajv/dist/2020').default;
  const ajv = new Ajv2020({ strict: false, allErrors: true });
  for (const name of ['location_2D', 'commission', 'robot_state']) {
    ajv.addSchema(JSON.parse(readFileSync(join(sourceDir, `tests/data/open_rmf_api/${name}.json`), 'utf8')));
  }
  return ajv.getSchema('https://raw.githubusercontent.com/open-rmf/rmf_api_msgs/main/rmf_api_msgs/schemas/robot_state.json');
})();

const robotState = async (url) => {
  const { status, body } = await getJson(`${url}/api/v1/rmf/robot_state`);
  assert.equal(status, 200);
  api.check('RmfRobotState', body);
  assert.ok(rmfSchema(body), JSON.stringify(rmfSchema.errors));
  return body;
};
const completed = async (url, cmdId) => {
  const { status, body } = await getJson(`${url}/api/v1/rmf/is_command_completed?cmd_id=${cmdId}`);
  assert.equal(status, 200, JSON.stringify(body));
  api.check('RmfCommandStatus', body);
  return body;
};

describe('the Open-RMF robot contract', () => {
  let daemon;
  let dir;
  let map;
  before(async () => {
    dir = mkdtempSync(join(tmpdir(), 'corridor-rmf-'));
    daemon = await startDaemon({ config: `
sim:
  world: "${writeRoom(dir, 4, 3)}"
  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 0}
  camera: {width: 160, height: 120}
  dock: {enabled: true, x_m: 3.2, y_m: 1.5, yaw_deg: 0}
webhooks:
  robot: "corridor-1"
` });
    map = (await getJson(`${daemon.url}/api/v1/rmf/map`)).body.map_name;
  });
  after(async () => {
    await daemon?.stop();
    rmSync(dir, { recursive: true, force: true });
  });

  test('position, battery and map as the template reads them; the state is Open-RMF\'s robot_state', async () => {
    assert.equal(map, 'room');
    const position = await getJson(`${daemon.url}/api/v1/rmf/position`);
    api.check('RmfPosition', position.body);
    const [x, y] = position.body.position;
    assert.ok(Math.hypot(x - 1.0, y - 1.0) < 0.05, JSON.stringify(position.body));
    const soc = await getJson(`${daemon.url}/api/v1/rmf/battery_soc`);
    api.check('RmfBatterySoc', soc.body);
    assert.ok(soc.body.battery_soc > 0.7 && soc.body.battery_soc <= 0.8, JSON.stringify(soc.body));
    const state = await robotState(daemon.url);
    assert.equal(state.name, 'corridor-1');
    assert.equal(state.status, 'idle');
    assert.equal(state.task_id, '');
    assert.equal(state.location.map, 'room');
  });

  test('navigate: the state says working, the command active, until stop cancels it', async () => {
    const res = await postJson(`${daemon.url}/api/v1/rmf/navigate`,
      { cmd_id: 7, pose: [2.5, 2.2, Math.PI / 2], map_name: map, speed_limit: 0.0 });
    assert.equal(res.status, 201, JSON.stringify(res.body));
    api.check('RmfCommandStarted', res.body);
    const working = await robotState(daemon.url);
    assert.equal(working.status, 'working');
    assert.equal(working.task_id, res.body.mission);
    assert.equal((await completed(daemon.url, 7)).completed, false);
    const stop = await postJson(`${daemon.url}/api/v1/rmf/stop`, { cmd_id: 9 });
    assert.equal(stop.status, 200);
    api.check('RmfCommandDone', stop.body);
    assert.equal((await completed(daemon.url, 7)).status, 'canceled');
    await waitFor(() => robotState(daemon.url), (s) => s.status === 'idle', 5000, 'idle');
  });

  test('bad calls get a problem and start nothing', async () => {
    const before = (await getJson(`${daemon.url}/api/v1/state`)).body.mission?.id;
    const cases = [
      ['navigate', { cmd_id: 1, pose: [1, 1, 0], map_name: 'L2' }, 422, 'wrong_map'],
      ['navigate', { cmd_id: -1, pose: [1, 1, 0], map_name: map }, 400],
      ['navigate', { cmd_id: 1, pose: [1, 1], map_name: map }, 400],
      ['navigate', { cmd_id: 1, pose: [1, 1, 0], map_name: map, speed_limit: -1 }, 400],
      ['navigate', { cmd_id: 1, pose: [1, 1, 0], map_name: map, colour: 'red' }, 400],
      ['navigate', { cmd_id: 1, pose: [40, 1, 0], map_name: map }, 422, 'goal_outside_map'],
      ['dock', { cmd_id: 1, dock_name: 'garage' }, 422, 'unknown_place'],
      ['start_activity', { cmd_id: 1, activity: 'dance' }, 422, 'unknown_activity'],
      ['stop', {}, 400],
      ['localize', { cmd_id: 1, pose: [1, 1, 0], map_name: map }, 409],
    ];
    for (const [route, body, status, code] of cases) {
      const res = await postJson(`${daemon.url}/api/v1/rmf/${route}`, body);
      assert.equal(res.status, status, `${route} ${JSON.stringify(body)}: ${JSON.stringify(res.body)}`);
      api.check('Problem', res.body);
      if (code) assert.equal(res.body.code, code);
    }
    assert.equal((await getJson(`${daemon.url}/api/v1/rmf/is_command_completed?cmd_id=12345`)).status, 404);
    assert.equal((await getJson(`${daemon.url}/api/v1/rmf/is_command_completed`)).status, 400);
    assert.equal((await getJson(`${daemon.url}/api/v1/state`)).body.mission?.id, before, 'no mission started');
  });
});
