// VDA 5050 2.1 over MQTT through corridord's own transport: a master control (mosquitto_sub and mosquitto_pub, on a
// mosquitto broker this test starts with a plain listener on loopback) sees the robot go online, its states and the
// factsheet; bad orders are refused with the standard's errors; an order with a horizon shows in the API and the
// console; the broker stopping and coming back loses no order; the broker's last will tells of a crashed robot. Every
// message the robot sends must validate against the standard's schemas (server/fleet/vda5050, copied from the VDA's
// 2.1.0 release), checked here by an independent validator (ajv). The order logic in simulated time (driving to the
// decision point at the edge's speed, updates, pause, cancel, refusal on arrival, charging) is
// tests/vda5050_lockstep_test.cc.
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  getJson, launchBrowser, openApiValidator, openConsole, require, sleep, sourceDir, startDaemon, waitFor, writeRoom,
} from './daemon.mjs';
import { Broker, freePort, publish, subscribe } from './mqtt.mjs';

const MAP = 'room';
const PREFIX = 'uagv/v2/corridor/r1';

const schemas = (() => {
  const Ajv2020 = require('ajv/dist/2020').default;
  const ajv = new Ajv2020({ strict: false, allErrors: true });
  const out = {};
  for (const name of ['state', 'connection', 'visualization', 'factsheet', 'order', 'instantActions']) {
    out[name] = ajv.compile(JSON.parse(readFileSync(join(sourceDir, `server/fleet/vda5050/${name}.schema`), 'utf8')));
  }
  return out;
})();

// The master control: everything the robot publishes, each checked against its schema as it arrives; and what it
// sends, checked before it goes.
class Master {
  constructor(port) {
    this.port = port;
    this.messages = [];  // {topic, body, at}
    this.invalid = [];
    this.headerId = 0;
    // Its own probe topic too: a probe it hears back says its subscriptions are in place (ready()).
    const topics = ['state', 'connection', 'visualization', 'factsheet', 'probe'].map((t) => `${PREFIX}/${t}`);
    this.proc = subscribe(port, topics, (full, payload) => {
      const topic = full.slice(PREFIX.length + 1);
      if (topic === 'probe') {
        this.probed = true;
        return;
      }
      const body = JSON.parse(payload);
      if (!schemas[topic](body)) {
        this.invalid.push({ topic, errors: schemas[topic].errors, body });
      }
      this.messages.push({ topic, body, at: Date.now() });
    });
  }
  stop() { this.proc.kill('SIGTERM'); }
  // Resolves once the broker delivers to this master: probes until one comes back.
  async ready() {
    const end = Date.now() + 10000;
    while (!this.probed) {
      if (Date.now() > end) throw new Error('the master never heard its own probe');
      this.sendRaw('probe', '{}');
      await sleep(50);
    }
  }
  publish(topic, body) {
    const message = { headerId: this.headerId++, timestamp: new Date().toISOString(), version: '2.1.0',
      manufacturer: 'corridor', serialNumber: 'r1', ...body };
    assert.ok(schemas[topic](message), JSON.stringify(schemas[topic].errors));
    this.sendRaw(topic, JSON.stringify(message));
  }
  sendRaw(topic, text) {
    publish(this.port, `${PREFIX}/${topic}`, text);
  }
  instant(type, id, params = []) {
    this.publish('instantActions', { actions: [{ actionType: type, actionId: id, blockingType: 'HARD',
      actionParameters: params }] });
  }
  last(topic) {
    const found = this.messages.findLast((m) => m.topic === topic);
    return found?.body;
  }
  // The first `topic` message after index `since` for which `predicate` holds.
  async waitFor(topic, predicate, ms, what, since = 0) {
    const end = Date.now() + ms;
    for (;;) {
      for (let i = since; i < this.messages.length; ++i) {
        const m = this.messages[i];
        if (m.topic === topic && predicate(m.body)) return m.body;
      }
      if (Date.now() > end) {
        const last = JSON.stringify(this.last(topic))?.slice(0, 900);
        throw new Error(`timed out waiting for ${what}; last ${topic}: ${last}`);
      }
      await sleep(50);
    }
  }
}

const node = (id, sequenceId, released, x, y, actions = [], theta = undefined) => ({
  nodeId: id, sequenceId, released, actions,
  nodePosition: { x, y, mapId: MAP, ...(theta === undefined ? {} : { theta }) },
});
const edge = (from, to, sequenceId, released, extra = {}) => ({
  edgeId: `${from}-${to}`, sequenceId, released, startNodeId: from, endNodeId: to, actions: [], ...extra,
});
const nodeIds = (state) => state.nodeStates.map((n) => n.nodeId);
const action = (state, id) => state.actionStates.find((a) => a.actionId === id)?.actionStatus;
const near = (state, x, y, tolerance) =>
  Math.hypot(state.agvPosition.x - x, state.agvPosition.y - y) < tolerance;

describe('VDA 5050 over MQTT', () => {
  let dir;
  let broker;
  let master;
  let daemon;
  before(async () => {
    dir = mkdtempSync(join(tmpdir(), 'corridor-vda-'));
    const port = await freePort();
    broker = new Broker(dir, port);
    await broker.start();
    master = new Master(port);
    await master.ready();  // subscribed before the robot says it is online
    daemon = await startDaemon({ config: `
sim:
  world: "${writeRoom(dir, 6, 3)}"
  start: {x_m: 1.0, y_m: 1.5, yaw_deg: 0}
  camera: {width: 160, height: 120}
fleet:
  vda5050: {serial_number: r1, state_interval_s: 2}
`, args: ['--mqtt', `mqtt://127.0.0.1:${port}`] });
  });
  after(async () => {
    master?.stop();
    await daemon?.stop();
    await broker?.stop();
    rmSync(dir, { recursive: true, force: true });
  });

  test('online, a valid state at least every interval, and the factsheet on request', async () => {
    await master.waitFor('connection', (m) => m.connectionState === 'ONLINE', 15000, 'ONLINE');
    // Until the base first reports its battery, the state says it is unknown (a warning), not empty.
    const known = (s) => !s.errors.some((e) => e.errorType === 'batteryUnknown');
    const first = await master.waitFor('state', (s) => s.agvPosition?.positionInitialized && known(s), 10000,
      'a state with the position and the battery');
    assert.equal(first.agvPosition.mapId, MAP);
    assert.equal(first.operatingMode, 'AUTOMATIC');
    assert.ok(first.batteryState.batteryCharge > 70);
    // Unchanged, the state still comes at least every state_interval_s (2 s here).
    const count = master.messages.length;
    const next = await master.waitFor('state', () => true, 4000, 'a periodic state', count);
    assert.equal(next.headerId > first.headerId, true);
    await master.waitFor('visualization', () => true, 3000, 'a visualization', count);
    master.instant('factsheetRequest', 'f1');
    const factsheet = await master.waitFor('factsheet', () => true, 5000, 'the factsheet');
    const types = factsheet.protocolFeatures.agvActions.map((a) => a.actionType);
    for (const t of ['startPause', 'stopPause', 'cancelOrder', 'startCharging', 'stopCharging', 'say']) {
      assert.ok(types.includes(t), t);
    }
    await master.waitFor('state', (s) => action(s, 'f1') === 'FINISHED', 5000, 'factsheetRequest finished');
  });

  test('an order with a horizon where the robot stands: the API and the console show it waiting', async () => {
    const here = master.last('state').agvPosition;
    master.publish('order', { orderId: 'o1', orderUpdateId: 0,
      nodes: [node('a', 0, true, here.x, here.y), node('b', 2, false, 4.0, 1.5)],
      edges: [edge('a', 'b', 1, false)] });
    const taken = await master.waitFor('state', (s) => s.orderId === 'o1' && s.lastNodeId === 'a', 5000,
      'the order taken');
    assert.deepEqual(nodeIds(taken), ['b']);
    const { body: robot } = await getJson(`${daemon.url}/api/v1/state`);
    openApiValidator().check('State', robot);
    assert.equal(robot.fleet.connected, true);
    assert.deepEqual(robot.fleet.nodes.map((n) => [n.id, n.released, n.traversed]).at(-1), ['b', false, false]);
    const browser = await launchBrowser();
    try {
      const { page, errors } = await openConsole(browser, daemon.url);
      await page.getByTestId('fleet').filter({ hasText: 'order o1/0, waiting for the order to be extended' })
        .waitFor({ timeout: 5000 });
      await page.locator('.fleet-node.fleet-horizon').waitFor({ timeout: 5000 });
      // (A straight line's box may have no height: attached, not visible.)
      await page.locator('.fleet-edge.fleet-horizon').waitFor({ state: 'attached', timeout: 5000 });
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
    // An update that keeps the horizon, so that an older one can be refused below.
    master.publish('order', { orderId: 'o1', orderUpdateId: 1,
      nodes: [node('a', 0, true, here.x, here.y), node('b', 2, false, 4.0, 1.5)],
      edges: [edge('a', 'b', 1, false)] });
    await master.waitFor('state', (s) => s.orderUpdateId === 1, 5000, 'the update taken');
  });

  test('bad orders are refused with the standard\'s errors and change nothing', async () => {
    let count = master.messages.length;
    master.sendRaw('order', '{"orderId": ');
    await master.waitFor('state', (s) => s.errors.some((e) => e.errorType === 'validationError'), 5000,
      'validationError for broken JSON', count);
    count = master.messages.length;
    master.sendRaw('order', JSON.stringify({ orderId: 'o9', nodes: 'none' }));
    await master.waitFor('state', (s) => s.errors.some((e) => e.errorType === 'validationError' &&
      /order/.test(e.errorDescription)), 5000, 'validationError for a schema breach', count);
    // Another order while o1 still has its horizon: refused.
    count = master.messages.length;
    master.publish('order', { orderId: 'o2', orderUpdateId: 0, nodes: [node('x', 0, true, 4.0, 1.5)], edges: [] });
    const refused = await master.waitFor('state', (s) => s.errors.some((e) => e.errorType === 'orderUpdateError'),
      5000, 'orderUpdateError', count);
    assert.equal(refused.orderId, 'o1');
    // An older update: refused too.
    count = master.messages.length;
    master.publish('order', { orderId: 'o1', orderUpdateId: 0, nodes: [node('a', 0, true, 1.0, 1.5)], edges: [] });
    await master.waitFor('state', (s) => s.errors.filter((e) => e.errorType === 'orderUpdateError').length >= 2,
      5000, 'a second orderUpdateError', count);
    // An action it cannot do.
    count = master.messages.length;
    master.instant('pick', 'k1');
    await master.waitFor('state', (s) => action(s, 'k1') === 'FAILED', 5000, 'pick failed', count);
    assert.deepEqual(nodeIds(master.last('state')), ['b']);
    master.instant('cancelOrder', 'c1');
    await master.waitFor('state', (s) => action(s, 'c1') === 'FINISHED', 5000, 'cancelled');
  });

  test('the broker stopping and coming back loses no order', async () => {
    const here = master.last('state').agvPosition;
    master.publish('order', { orderId: 'o3', orderUpdateId: 0,
      nodes: [node('c', 0, true, here.x, here.y), node('e', 2, true, 1.5, 1.0), node('f', 4, false, 1.0, 1.5)],
      edges: [edge('c', 'e', 1, true), edge('e', 'f', 3, false)] });
    await master.waitFor('state', (s) => s.orderId === 'o3' && s.driving, 10000, 'driving o3');
    await broker.stop();
    // Away until the robot knows it (it goes on driving meanwhile).
    await waitFor(async () => (await getJson(`${daemon.url}/api/v1/state`)).body.fleet, (f) => !f.connected, 10000,
      'the robot seeing the broker gone');
    await broker.start();
    const count = master.messages.length;
    // Back online by itself; the order went on meanwhile (e reached while the broker was away, or after).
    await master.waitFor('connection', (m) => m.connectionState === 'ONLINE', 20000, 'online again', count);
    const atE = await master.waitFor('state', (s) => s.orderId === 'o3' && s.lastNodeId === 'e', 30000,
      'e reached', count);
    assert.deepEqual(nodeIds(atE), ['f']);
    // An update after the reconnection is taken and driven.
    master.publish('order', { orderId: 'o3', orderUpdateId: 1,
      nodes: [node('e', 2, true, 1.5, 1.0), node('f', 4, true, 1.0, 1.5)], edges: [edge('e', 'f', 3, true)] });
    const done = await master.waitFor('state', (s) => s.lastNodeId === 'f' && s.nodeStates.length === 0, 30000,
      'f reached', count);
    assert.ok(near(done, 1.0, 1.5, 0.3), JSON.stringify(done.agvPosition));
  });

  test('every message the robot sent was valid; a crash leaves the broker\'s last will', async () => {
    assert.deepEqual(master.invalid.map((m) => `${m.topic}: ${JSON.stringify(m.errors)}`), []);
    assert.ok(master.messages.filter((m) => m.topic === 'state').length > 10);
    const count = master.messages.length;
    daemon.kill('SIGKILL');
    await daemon.exited;
    const will = await master.waitFor('connection', (m) => m.connectionState === 'CONNECTIONBROKEN', 30000,
      'the last will', count);
    assert.equal(will.serialNumber, 'r1');
    rmSync(daemon.stateDir, { recursive: true, force: true });
    daemon = null;
  });
});
