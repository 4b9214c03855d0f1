// A building of two floors made of two bundled maps (floor L1: the Willow Garage office; floor L2: the small house)
// with a lift between them, and the building's lift controller as a real HTTP server in this test (what the daemon
// calls with the requests in building.controller). The controller drives the simulated lift through corridord's
// /api/v1/sim/lifts, as a real one drives the car. A mission from L1 to a place on L2 calls the lift, waits for its
// door, boards, rides, switches to L2's map with the pose the car carried over, leaves and arrives; a lift that
// refuses ends the mission with the controller's reason and the robot never boards. The same ride again with a lift
// that speaks Open-RMF's LiftRequest and LiftState over MQTT (a broker this test starts, and an RMF lift adapter
// built on mosquitto_sub and mosquitto_pub). The robot starts 1.3 m (by its path) north of the lift's lobby (from the east, the
// office's furniture makes it 7.5 m round): how rides behave (phases,
// localization across the floors, a ride cancelled in the car) is tested in simulated time,
// tests/lifts_lockstep_test.cc; here it is the controllers' transports.
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { createServer } from 'node:http';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import { apiFetch, getJson, openApiValidator, postJson, sourceDir, startDaemon, waitFor } from './daemon.mjs';
import { Broker, freePort, publish, subscribe } from './mqtt.mjs';

const api = openApiValidator();

// The building: L1 the Willow Garage office, L2 the small house, one lift; `controller` is the lift controller's
// YAML (indented for building.controller).
function buildingConfig(controller) {
  const worlds = join(sourceDir, 'config/worlds');
  return `
building:
  name: two floors
  floors:
    - {name: L1, map: "${worlds}/willow_garage/willow-full-0.05.yaml"}
    - {name: L2, map: "${worlds}/small_house/maps/map.yaml"}
  lifts:
    - id: lift1
      stops:
        - {floor: L1, x1_m: 18.1, y1_m: 21.55, x2_m: 18.1, y2_m: 22.45,
           lobby_x_m: 18.9, lobby_y_m: 22.0, lobby_yaw_deg: 180}
        - {floor: L2, x1_m: 2.9, y1_m: 0.55, x2_m: 2.9, y2_m: 1.45, lobby_x_m: 2.1, lobby_y_m: 1.0, lobby_yaw_deg: 0}
  controller:
${controller}
  sim: {travel_s: 3}
localization: {source: mcl}
sim:
  start: {x_m: 19.5, y_m: 23.0, yaw_deg: -90}
  camera: {width: 160, height: 120}
  dock: {enabled: false}
`;
}

// Starts a mission to (0.8, 1.0) on L2, 1.3 m past the lobby, and waits until it is over; returns the mission and the
// lift phases seen.
async function rideToL2(daemon) {
  const started = await postJson(`${daemon.url}/api/v1/missions`,
    { waypoints: [{ x: 0.8, y: 1.0, yaw: 3.14, floor: 'L2' }] });
  assert.equal(started.status, 201, JSON.stringify(started.body));
  const url = `${daemon.url}/api/v1/missions/${started.body.id}`;
  const phases = new Set();
  const done = await waitFor(async () => {
    const { body } = await getJson(url);
    if (body.lift) phases.add(body.lift);
    return body;
  }, (m) => ['succeeded', 'failed', 'canceled'].includes(m.status), 240000, 'the mission over');
  return { done, phases };
}

// At the goal on L2, by the simulator's truth (in L2's frame) and by localization.
async function assertArrivedOnL2(daemon) {
  const { body: state } = await getJson(`${daemon.url}/api/v1/state`);
  assert.equal(state.floor, 'L2');
  assert.equal(state.map.name, 'map');
  assert.ok(Math.hypot(state.sim_true_pose.x - 0.8, state.sim_true_pose.y - 1.0) < 0.15,
    JSON.stringify(state.sim_true_pose));
  assert.ok(Math.hypot(state.pose.x - state.sim_true_pose.x, state.pose.y - state.sim_true_pose.y) < 0.15,
    `${JSON.stringify(state.pose)} vs ${JSON.stringify(state.sim_true_pose)}`);
}

// The building's lift controller: takes calls (or refuses, when told to), says where the car is and whether its door
// is open, and closes the door when released; it moves the simulated car through the daemon's simulator routes.
class LiftController {
  constructor() {
    this.refuse = false;
    this.calls = [];
    this.daemon = null;
    this.server = createServer((req, res) => this.handle(req, res));
  }
  listen() { return new Promise((r) => this.server.listen(0, '127.0.0.1', () => r(this.server.address().port))); }
  close() {
    this.server.closeAllConnections();
    return new Promise((r) => this.server.close(r));
  }
  async sim(path, method = 'GET', body = undefined) {
    const res = await apiFetch(`${this.daemon.url}/api/v1/sim/lifts/${path}`, {
      method, headers: body ? { 'Content-Type': 'application/json' } : {},
      body: body ? JSON.stringify(body) : undefined });
    return { status: res.status, body: await res.json() };
  }
  async handle(req, res) {
    const m = /^\/lifts\/([^/]+)(\/release)?$/.exec(req.url);
    if (!m) { res.writeHead(404).end(); return; }
    const [, lift, release = ''] = m;
    let text = '';
    for await (const chunk of req) text += chunk;
    this.calls.push(`${req.method} ${release || 'lift'} ${text}`.trim());
    if (req.method === 'GET' && !release) {
      const { status, body } = await this.sim(lift);
      res.writeHead(status, { 'Content-Type': 'application/json' }).end(JSON.stringify(body));
    } else if (req.method === 'PUT' && !release) {
      if (this.refuse) { res.writeHead(409).end('out of service for maintenance'); return; }
      const { status } = await this.sim(lift, 'PUT', JSON.parse(text));
      res.writeHead(status === 200 ? 202 : status).end();
    } else if (req.method === 'POST' && release) {
      const { status } = await this.sim(`${lift}/release`, 'POST');
      res.writeHead(status).end();
    } else {
      res.writeHead(405).end();
    }
  }
}

describe('lifts between floors', () => {
  let daemon;
  let controller;
  before(async () => {
    controller = new LiftController();
    const port = await controller.listen();
    const base = `http://127.0.0.1:${port}/lifts/{lift}`;
    daemon = await startDaemon({ config: buildingConfig(`
    call: {method: PUT, url: "${base}", body: '{"floor": "{floor}"}'}
    state: {method: GET, url: "${base}"}
    release: {method: POST, url: "${base}/release"}
    poll_s: 0.3`) });
    controller.daemon = daemon;
  });
  after(async () => {
    await controller?.close();
    await daemon?.stop();
  });

  test('the building, its floors and its lift are in the API; the simulated lift is driven through its own',
    async () => {
      const { status, body } = await getJson(`${daemon.url}/api/v1/building`);
      assert.equal(status, 200);
      api.check('Building', body);
      assert.equal(body.floor, 'L1');
      assert.deepEqual(body.floors.map((f) => [f.name, f.map]), [['L1', 'willow-full-0.05'], ['L2', 'map']]);
      assert.ok(Math.abs(body.lifts[0].stops[0].car.x - 17.4) < 1e-9);
      const { body: lifts } = await getJson(`${daemon.url}/api/v1/sim/lifts`);
      api.check('SimLifts', lifts);
      assert.deepEqual(lifts.lifts, [{ id: 'lift1', floor: 'L1', destination: '', door: 'closed' }]);
      const bad = await apiFetch(`${daemon.url}/api/v1/sim/lifts/lift1`, {
        method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: '{"floor": "L9"}' });
      assert.equal(bad.status, 422);
      const off = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 0, y: 0, floor: 'L7' }] });
      assert.equal(off.status, 422);
      assert.equal(off.body.code, 'unknown_floor');
      const wall = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 0.0, y: -2.5, floor: 'L2' }] });
      assert.equal(wall.status, 422, JSON.stringify(wall.body));
    });

  test('a lift that refuses ends the mission with its reason; the robot never boards', async () => {
    controller.refuse = true;
    const started = await postJson(`${daemon.url}/api/v1/missions`,
      { waypoints: [{ x: -1.0, y: 0.5, floor: 'L2' }] });
    assert.equal(started.status, 201, JSON.stringify(started.body));
    api.check('Mission', started.body);
    assert.deepEqual(started.body.waypoints.map((w) => w.action), ['ride_lift', 'go']);
    const done = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/missions/${started.body.id}`)).body,
      (m) => m.status !== 'active', 120000, 'the mission over');
    assert.equal(done.status, 'failed');
    assert.match(done.error, /lift lift1 refused: 409 Conflict: out of service for maintenance/);
    const { body: state } = await getJson(`${daemon.url}/api/v1/state`);
    assert.equal(state.floor, 'L1');
    assert.ok(state.sim_true_pose.x > 18.1 + 0.2, JSON.stringify(state.sim_true_pose));  // outside the car
  });

  test('a mission from floor L1 to a place on floor L2 rides the lift and arrives', async () => {
    controller.refuse = false;
    controller.calls = [];
    const { done, phases } = await rideToL2(daemon);
    assert.equal(done.status, 'succeeded', done.error);
    api.check('Mission', done);
    // Sampled by polling: a call the car answers at once (it waits at L1) can pass between two polls, so the call is
    // checked at the controller below.
    for (const phase of ['boarding', 'riding', 'leaving']) assert.ok(phases.has(phase), [...phases].join());
    await assertArrivedOnL2(daemon);
    assert.deepEqual(controller.calls.filter((c) => !c.startsWith('GET')),
      ['PUT lift {"floor": "L1"}', 'PUT lift {"floor": "L2"}', 'POST /release']);
    const { body: lifts } = await getJson(`${daemon.url}/api/v1/sim/lifts`);
    assert.deepEqual(lifts.lifts, [{ id: 'lift1', floor: 'L2', destination: '', door: 'closed' }]);
  });
});

// An RMF lift adapter: takes LiftRequests (AGV_MODE: the car to destination_floor in this session; END_SESSION),
// drives the simulated car through the daemon's simulator routes, and publishes LiftState every 300 ms.
class RmfLiftAdapter {
  constructor(port) {
    this.port = port;
    this.requests = [];
    this.session = '';
    this.mode = 2;  // AGV
    this.sub = subscribe(port, ['rmf/lift_requests'], (topic, text) => this.request(JSON.parse(text)));
  }
  async sim(path, method = 'GET', body = undefined) {
    const res = await apiFetch(`${this.daemon.url}/api/v1/sim/lifts/${path}`, {
      method, headers: body ? { 'Content-Type': 'application/json' } : {},
      body: body ? JSON.stringify(body) : undefined });
    return res.json();
  }
  async request(r) {
    this.requests.push(r);
    if (r.request_type === 1) {
      this.session = r.session_id;
      await this.sim(r.lift_name, 'PUT', { floor: r.destination_floor });
    } else if (r.request_type === 0 && r.session_id === this.session) {
      this.session = '';
      await this.sim(`${r.lift_name}/release`, 'POST');
    }
  }
  start(daemon) {
    this.daemon = daemon;
    this.timer = setInterval(async () => {
      const lift = await this.sim('lift1');
      publish(this.port, 'rmf/lift_states', JSON.stringify({
        lift_time: { sec: Math.floor(Date.now() / 1000), nanosec: 0 }, lift_name: 'lift1',
        available_floors: ['L1', 'L2'], current_floor: lift.floor, destination_floor: lift.destination || lift.floor,
        door_state: lift.door === 'open' ? 2 : 0, motion_state: lift.destination ? 1 : 0, available_modes: [1, 2],
        current_mode: this.mode, session_id: this.session }));
    }, 300);
  }
  stop() {
    clearInterval(this.timer);
    this.sub.kill('SIGTERM');
  }
}

describe('a lift that speaks Open-RMF over MQTT', () => {
  let dir;
  let broker;
  let adapter;
  let daemon;
  before(async () => {
    dir = mkdtempSync(join(tmpdir(), 'corridor-rmf-lift-'));
    broker = new Broker(dir, await freePort());
    await broker.start();
    adapter = new RmfLiftAdapter(broker.port);
    daemon = await startDaemon({ config: buildingConfig(`
    mqtt: {broker: "${broker.url}", prefix: rmf, requester_id: r1}
    poll_s: 0.3`) });
    adapter.start(daemon);
  });
  after(async () => {
    adapter?.stop();
    await daemon?.stop();
    await broker?.stop();
    rmSync(dir, { recursive: true, force: true });
  });

  test('LiftRequests in a session of its own take the robot to L2; the session ends after', async () => {
    const { done } = await rideToL2(daemon);
    assert.equal(done.status, 'succeeded', done.error);
    await assertArrivedOnL2(daemon);
    // Each request in force is sent again every 2 s, as RMF's adapters do: the distinct ones, in order.
    const asked = adapter.requests.map((r) => [r.request_type, r.destination_floor, r.session_id])
      .filter((r, i, all) => i === 0 || JSON.stringify(r) !== JSON.stringify(all[i - 1]));
    assert.deepEqual(asked, [[1, 'L1', 'r1'], [1, 'L2', 'r1'], [0, '', 'r1']]);
    assert.equal(adapter.requests[0].door_state, 2);
  });

  test('a lift in fire mode refuses: the mission ends saying so', async () => {
    adapter.mode = 3;  // FIRE
    const started = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 20.0, y: 24.4, floor: 'L1' }] });
    assert.equal(started.status, 201, JSON.stringify(started.body));
    const done = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/missions/${started.body.id}`)).body,
      (m) => ['succeeded', 'failed', 'canceled'].includes(m.status), 60000, 'the mission over');
    assert.equal(done.status, 'failed');
    assert.match(done.error, /lift lift1 refused: the lift is in fire mode/);
    const { body: state } = await getJson(`${daemon.url}/api/v1/state`);
    assert.equal(state.floor, 'L2');
  });
});
