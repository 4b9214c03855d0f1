// Doors on the way: two rooms joined by a doorway with a simulated door in it, and the building's door controller as a
// real HTTP server in this test (what the daemon calls with the requests in doors.controller). The controller moves
// the simulated door through corridord's /api/v1/sim/doors, as a real one drives its motor. A mission through the
// door asks for it ahead, waits short of it until it is open, passes, and releases it; a door that refuses ends the
// mission before the robot reaches it, as does a controller that stops answering (after doors.timeout_s), and the
// robot never drives into the closed door. The same door again behind Open-RMF's DoorRequest and DoorState over MQTT
// (a broker this test starts, and an RMF door adapter built on mosquitto_sub and mosquitto_pub).
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import { apiFetch, getJson, openApiValidator, postJson, startDaemon, waitFor } from './daemon.mjs';
import { Broker, freePort, publish, subscribe } from './mqtt.mjs';

const api = openApiValidator();

// An 8 x 3 m map split by a wall at x = 4 with a 1 m doorway at y 1..2.
function writeTwoRooms(dir) {
  const res = 0.05;
  const w = Math.round(8 / res) + 2;
  const h = Math.round(3 / res) + 2;
  const pixels = Buffer.alloc(w * h, 254);
  for (let row = 0; row < h; ++row) {
    for (let col = 0; col < w; ++col) {
      const x = (col - 1 + 0.5) * res;
      const y = (h - 1 - row - 1 + 0.5) * res;
      const border = row === 0 || col === 0 || row === h - 1 || col === w - 1;
      const wall = Math.abs(x - 4.0) < 0.05 && (y < 1.0 || y > 2.0);
      if (border || wall) pixels[row * w + col] = 0;
    }
  }
  writeFileSync(join(dir, 'rooms.pgm'), Buffer.concat([Buffer.from(`P5\n${w} ${h}\n255\n`), pixels]));
  writeFileSync(join(dir, 'rooms.yaml'),
    'image: rooms.pgm\nresolution: 0.05\norigin: [-0.05, -0.05, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n');
  return join(dir, 'rooms.yaml');
}

// The simulator in the two rooms with its door d1 in the doorway (closed), the robot in the left room.
function twoRoomsConfig(dir) {
  return `
sim:
  world: "${writeTwoRooms(dir)}"
  start: {x_m: 2.0, y_m: 1.5, yaw_deg: 0}
  camera: {width: 160, height: 120}
  dock: {enabled: false}
  doors:
    - {id: d1, x1_m: 4.0, y1_m: 1.0, x2_m: 4.0, y2_m: 2.0}`;
}

// The building's door controller: opens a door five seconds after it is asked (or refuses, when told to), says how it
// is, and closes it when released.
class DoorController {
  constructor() {
    this.refuse = false;
    this.silent = false;  // takes requests to open, then never answers how the door is
    this.states = new Map();
    this.calls = [];
    this.timers = new Set();
    this.daemon = null;
    this.server = createServer((req, res) => this.handle(req, res));
  }
  listen() { return new Promise((r) => this.server.listen(0, '127.0.0.1', () => r(this.server.address().port))); }
  close() {
    for (const t of this.timers) clearTimeout(t);
    this.server.closeAllConnections();
    return new Promise((r) => this.server.close(r));
  }
  later(ms, work) {
    const timer = setTimeout(() => { this.timers.delete(timer); work(); }, ms);
    this.timers.add(timer);
  }
  async move(door, open) {
    const res = await apiFetch(`${this.daemon.url}/api/v1/sim/doors/${door}`, {
      method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ open }) });
    assert.equal(res.status, 200, await res.text());
    this.states.set(door, open ? 'open' : 'closed');
  }
  handle(req, res) {
    const m = /^\/doors\/([^/]+)(\/open|\/release)?$/.exec(req.url);
    if (!m) { res.writeHead(404).end(); return; }
    const [, door, action = ''] = m;
    this.calls.push(`${req.method} ${action || 'state'} ${door}`);
    if (req.method === 'GET' && !action) {
      if (this.silent) return;  // the request hangs until the daemon gives up on it
      res.writeHead(200, { 'Content-Type': 'application/json' })
        .end(JSON.stringify({ state: this.states.get(door) ?? 'closed' }));
    } else if (req.method === 'POST' && action === '/open') {
      if (this.refuse) { res.writeHead(403).end('locked for the night'); return; }
      this.states.set(door, 'opening');
      res.writeHead(202).end();
      // A slow door: the robot gets there first. (A silent controller never opens it.)
      if (!this.silent) this.later(5000, () => this.move(door, true));
    } else if (req.method === 'POST' && action === '/release') {
      res.writeHead(200).end();
      this.later(300, () => this.move(door, false));
    } else {
      res.writeHead(405).end();
    }
  }
}

describe('doors on the way', () => {
  let dir;
  let daemon;
  let controller;
  before(async () => {
    dir = mkdtempSync(join(tmpdir(), 'corridor-doors-'));
    controller = new DoorController();
    const port = await controller.listen();
    const base = `http://127.0.0.1:${port}/doors/{door}`;
    daemon = await startDaemon({ config: `${twoRoomsConfig(dir)}
doors:
  controller:
    open: {method: POST, url: "${base}/open"}
    state: {method: GET, url: "${base}"}
    release: {method: POST, url: "${base}/release"}
    poll_s: 0.3
    request_timeout_s: 1
  timeout_s: 10
` });
    controller.daemon = daemon;
  });
  after(async () => {
    await controller?.close();
    await daemon?.stop();
    rmSync(dir, { recursive: true, force: true });
  });

  test('the simulator\'s doors are listed and moved through its API', async () => {
    const { status, body } = await getJson(`${daemon.url}/api/v1/sim/doors`);
    assert.equal(status, 200);
    api.check('SimDoors', body);
    assert.deepEqual(body.doors, [{ id: 'd1', open: false }]);
    const bad = await apiFetch(`${daemon.url}/api/v1/sim/doors/nope`, {
      method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: '{"open": true}' });
    assert.equal(bad.status, 404);
  });

  test('a mission through the door asks for it, waits until it opens, passes and releases it', async () => {
    const started = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 6.0, y: 1.5 }] });
    assert.equal(started.status, 201, JSON.stringify(started.body));
    const id = started.body.id;
    // Waiting short of the door until the controller has opened it.
    const waiting = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/missions/${id}`)).body,
      (m) => m.waiting_for_door === 'd1', 20000, 'waiting for d1');
    assert.equal(waiting.policy, 'waiting_for_door');
    const { body: state } = await getJson(`${daemon.url}/api/v1/state`);
    assert.ok(state.sim_true_pose.x < 4.0 - 0.2 - 0.05, JSON.stringify(state.sim_true_pose));
    const done = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/missions/${id}`)).body,
      (m) => m.status !== 'active', 60000, 'the mission over');
    assert.equal(done.status, 'succeeded', done.error);
    const { body: after } = await getJson(`${daemon.url}/api/v1/state`);
    assert.ok(Math.hypot(after.sim_true_pose.x - 6.0, after.sim_true_pose.y - 1.5) < 0.1);
    await waitFor(async () => controller.calls, (c) => c.includes('POST /release d1'), 5000, 'released');
    assert.equal(controller.calls[0], 'POST /open d1');
    assert.ok(controller.calls.includes('GET state d1'));
    await waitFor(async () => (await getJson(`${daemon.url}/api/v1/sim/doors`)).body.doors[0].open, (o) => !o, 5000,
      'the door closed again');
  });

  test('a door that refuses ends the mission before the robot reaches it', async () => {
    controller.refuse = true;
    const started = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 2.0, y: 1.5 }] });
    assert.equal(started.status, 201, JSON.stringify(started.body));
    let nearest = Infinity;
    const done = await waitFor(async () => {
      const { body } = await getJson(`${daemon.url}/api/v1/state`);
      nearest = Math.min(nearest, body.sim_true_pose.x);
      return (await getJson(`${daemon.url}/api/v1/missions/${started.body.id}`)).body;
    }, (m) => m.status !== 'active', 30000, 'the mission over');
    assert.equal(done.status, 'failed');
    assert.match(done.error, /door d1 refused to open: 403 Forbidden: locked for the night/);
    assert.ok(nearest > 4.0 + 0.2, `the robot came to x ${nearest}`);
    // The door the controller refused stays shut.
    const doors = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/sim/doors`)).body.doors,
      (d) => d.length === 1 && d[0].id === 'd1' && !d[0].open, 5000, 'door d1 shut');
    assert.deepEqual(doors, [{ id: 'd1', open: false }]);
  });

  test('a controller that stops answering: the robot waits short of the door, then the mission ends saying so',
    async () => {
      controller.refuse = false;
      controller.silent = true;
      const started = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 2.0, y: 1.5 }] });
      assert.equal(started.status, 201, JSON.stringify(started.body));
      const url = `${daemon.url}/api/v1/missions/${started.body.id}`;
      await waitFor(async () => (await getJson(url)).body, (m) => m.waiting_for_door === 'd1', 20000, 'waiting');
      const done = await waitFor(async () => (await getJson(url)).body, (m) => m.status !== 'active', 20000,
        'the mission over');
      assert.equal(done.status, 'failed');
      assert.match(done.error, /door d1 did not open within 10 s/);
      const { body: state } = await getJson(`${daemon.url}/api/v1/state`);
      assert.ok(state.sim_true_pose.x > 4.0 + 0.2, JSON.stringify(state.sim_true_pose));
    });
});

describe('a door that speaks Open-RMF over MQTT', () => {
  let dir;
  let broker;
  let daemon;
  let sub;
  let timer;
  const requests = [];
  before(async () => {
    dir = mkdtempSync(join(tmpdir(), 'corridor-rmf-doors-'));
    broker = new Broker(dir, await freePort());
    await broker.start();
    daemon = await startDaemon({ config: `${twoRoomsConfig(dir)}
doors:
  controller:
    mqtt: {broker: "${broker.url}", prefix: site/rmf, requester_id: r1}
    poll_s: 0.3
  timeout_s: 20
` });
    // The RMF door adapter: a requested mode moves the simulated door a second later; DoorState every 300 ms.
    const move = (open) => apiFetch(`${daemon.url}/api/v1/sim/doors/d1`, {
      method: 'PUT', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify({ open }) });
    sub = subscribe(broker.port, ['site/rmf/door_requests'], (topic, text) => {
      const r = JSON.parse(text);
      requests.push(r);
      setTimeout(() => move(r.requested_mode.value === 2), 1000);
    });
    timer = setInterval(async () => {
      const { body } = await getJson(`${daemon.url}/api/v1/sim/doors`);
      publish(broker.port, 'site/rmf/door_states', JSON.stringify({
        door_time: { sec: Math.floor(Date.now() / 1000), nanosec: 0 }, door_name: 'd1',
        current_mode: { value: body.doors[0].open ? 2 : 0 } }));
    }, 300);
  });
  after(async () => {
    clearInterval(timer);
    sub?.kill('SIGTERM');
    await daemon?.stop();
    await broker?.stop();
    rmSync(dir, { recursive: true, force: true });
  });

  test('the door is asked open with a DoorRequest, passed once its DoorState says open, and asked closed', async () => {
    const started = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 6.0, y: 1.5 }] });
    assert.equal(started.status, 201, JSON.stringify(started.body));
    const done = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/missions/${started.body.id}`)).body,
      (m) => m.status !== 'active', 60000, 'the mission over');
    assert.equal(done.status, 'succeeded', done.error);
    await waitFor(async () => requests.length, (n) => n >= 2, 5000, 'the door asked closed');
    // The request in force is sent again every 2 s, as RMF's adapters do: the distinct ones, in order.
    const distinct = requests.map((r) => [r.door_name, r.requester_id, r.requested_mode.value])
      .filter((r, i, all) => i === 0 || JSON.stringify(r) !== JSON.stringify(all[i - 1]));
    assert.deepEqual(distinct, [['d1', 'r1', 2], ['d1', 'r1', 0]]);
  });
});
