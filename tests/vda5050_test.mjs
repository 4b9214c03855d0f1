// VDA 5050 2.1 over MQTT: a master control (mosquitto_sub and mosquitto_pub, on a mosquitto broker this test starts
// with a plain listener on loopback) drives the robot in a 6 x 3 m room with orders and instant actions. Every message
// the robot sends must validate against the standard's schemas (server/fleet/vda5050, copied from the VDA's 2.1.0
// release). The broker stopping and coming back loses no order; the broker's last will tells of a crashed robot.
import assert from 'node:assert/strict';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  getJson, launchBrowser, openApiValidator, openConsole, require, sleep, sourceDir, startDaemon, writeRoom,
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
    const topics = ['state', 'connection', 'visualization', 'factsheet'].map((t) => `${PREFIX}/${t}`);
    this.proc = subscribe(port, topics, (full, payload) => {
      const topic = full.slice(PREFIX.length + 1);
      const body = JSON.parse(payload);
      if (!schemas[topic](body)) {
        this.invalid.push({ topic, errors: schemas[topic].errors, body });
      }
      this.messages.push({ topic, body, at: Date.now() });
    });
  }
  stop() { this.proc.kill('SIGTERM'); }
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
const say = (id, text) => ({ actionType: 'say', actionId: id, blockingType: 'NONE',
  actionParameters: [{ key: 'text', value: text }] });
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
    await sleep(300);  // subscribed before the robot says it is online
    daemon = await startDaemon({ config: `
sim:
  world: "${writeRoom(dir, 6, 3)}"
  start: {x_m: 1.0, y_m: 1.5, yaw_deg: 0}
  camera: {width: 160, height: 120}
  dock: {enabled: true, x_m: 5.2, y_m: 1.5, yaw_deg: 0}
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

  test('an order with a horizon: driven to the decision point, extended by an update, paused and resumed', async () => {
    master.publish('order', { orderId: 'o1', orderUpdateId: 0,
      nodes: [node('a', 0, true, 1.0, 1.5), node('b', 2, true, 2.5, 1.5, [say('s1', 'node b')]),
        node('c', 4, false, 4.0, 1.5)],
      edges: [edge('a', 'b', 1, true, { maxSpeed: 0.3 }), edge('b', 'c', 3, false)] });
    const taken = await master.waitFor('state', (s) => s.orderId === 'o1', 5000, 'the order taken');
    assert.deepEqual(nodeIds(taken), ['b', 'c']);
    assert.equal(taken.lastNodeId, 'a');
    assert.equal(taken.edgeStates.length, 2);
    await master.waitFor('state', (s) => s.driving, 10000, 'driving');
    // The edge's maxSpeed holds the robot to 0.3 m/s.
    await sleep(1500);
    const fast = master.messages.filter((m) => m.topic === 'visualization' && m.body.velocity &&
      m.body.velocity.vx > 0.36);
    assert.equal(fast.length, 0, JSON.stringify(fast[0]?.body.velocity));
    // At b: the node is traversed, its action done; the robot stops at the decision point with c still waiting.
    const atB = await master.waitFor('state', (s) => s.lastNodeId === 'b', 30000, 'node b traversed');
    assert.deepEqual(nodeIds(atB), ['c']);
    assert.equal(action(atB, 's1'), 'FINISHED');
    assert.ok(near(atB, 2.5, 1.5, 0.3), JSON.stringify(atB.agvPosition));
    await master.waitFor('state', (s) => !s.driving && s.lastNodeId === 'b', 10000, 'stopped at b');
    await sleep(1000);
    assert.ok(near(master.last('state'), 2.5, 1.5, 0.3), 'waits at the decision point');
    // The API's state and the console show the order: c is the horizon, drawn hollow and dashed.
    const { body: robot } = await getJson(`${daemon.url}/api/v1/state`);
    openApiValidator().check('State', robot);
    assert.equal(robot.fleet.connected, true);
    assert.deepEqual(robot.fleet.nodes.map((n) => [n.id, n.released, n.traversed]),
      [['b', true, true], ['c', false, false]]);
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
    // The update stitches on b, releases c and adds a horizon d.
    master.publish('order', { orderId: 'o1', orderUpdateId: 1,
      nodes: [node('b', 2, true, 2.5, 1.5), node('c', 4, true, 4.0, 1.5), node('d', 6, false, 4.0, 2.2)],
      edges: [edge('b', 'c', 3, true), edge('c', 'd', 5, false)] });
    await master.waitFor('state', (s) => s.orderUpdateId === 1 && s.driving, 10000, 'driving to c');
    master.instant('startPause', 'p1');
    const paused = await master.waitFor('state', (s) => s.paused && action(s, 'p1') === 'FINISHED', 5000, 'paused');
    assert.deepEqual(nodeIds(paused), ['c', 'd']);
    await master.waitFor('state', (s) => s.paused && !s.driving, 5000, 'standing while paused');
    const stood = master.last('state').agvPosition;
    await sleep(1500);
    assert.ok(near(master.last('state'), stood.x, stood.y, 0.05), 'no driving while paused');
    master.instant('stopPause', 'p2');
    const atC = await master.waitFor('state', (s) => s.lastNodeId === 'c' && !s.paused, 30000, 'node c traversed');
    assert.deepEqual(nodeIds(atC), ['d']);
    assert.ok(near(atC, 4.0, 1.5, 0.3), JSON.stringify(atC.agvPosition));
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
    master.publish('order', { orderId: 'o1', orderUpdateId: 0, nodes: [node('c', 4, true, 4.0, 1.5)], edges: [] });
    await master.waitFor('state', (s) => s.errors.filter((e) => e.errorType === 'orderUpdateError').length >= 2,
      5000, 'a second orderUpdateError', count);
    // An action it cannot do.
    count = master.messages.length;
    master.instant('pick', 'k1');
    await master.waitFor('state', (s) => action(s, 'k1') === 'FAILED', 5000, 'pick failed', count);
    assert.deepEqual(nodeIds(master.last('state')), ['d']);
  });

  test('cancelOrder stops and drops the order; with none, noOrderToCancel', async () => {
    master.instant('cancelOrder', 'c1');
    const cancelled = await master.waitFor('state', (s) => action(s, 'c1') === 'FINISHED', 5000, 'cancelled');
    assert.deepEqual(nodeIds(cancelled), []);
    assert.equal(cancelled.orderId, 'o1');  // kept, as the standard says
    master.instant('cancelOrder', 'c2');
    const none = await master.waitFor('state', (s) => action(s, 'c2') === 'FAILED', 5000, 'nothing to cancel');
    const error = none.errors.find((e) => e.errorType === 'noOrderToCancel');
    assert.ok(error, JSON.stringify(none.errors));
    assert.equal(error.errorReferences[0].referenceValue, 'c2');
  });

  test('an order to a node the console would refuse is refused on arrival, naming the node, and nothing moves', async () => {
    const here = master.last('state').agvPosition;
    const count = master.messages.length;
    master.publish('order', { orderId: 'o7', orderUpdateId: 0,
      nodes: [node('s', 0, true, here.x, here.y), node('wall', 2, true, 3.0, 0.02)],
      edges: [edge('s', 'wall', 1, true)] });
    const refused = await master.waitFor('state', (s) => s.errors.some((e) => e.errorType === 'noRouteError'), 5000,
      'noRouteError', count);
    const error = refused.errors.find((e) => e.errorType === 'noRouteError');
    const reference = (key) => error.errorReferences.find((r) => r.referenceKey === key)?.referenceValue;
    assert.equal(reference('nodeId'), 'wall', JSON.stringify(error));
    assert.equal(reference('orderId'), 'o7');
    assert.equal(refused.orderId, 'o1', 'the refused order is not taken');
    assert.deepEqual(nodeIds(refused), []);
    // Nothing started: the robot stands where it stood.
    const later = await master.waitFor('state', () => true, 5000, 'a later state', master.messages.length);
    assert.equal(later.driving, false);
    assert.ok(near(later, here.x, here.y, 0.05), JSON.stringify(later.agvPosition));
  });

  test('the broker stopping and coming back loses no order', async () => {
    const here = master.last('state').agvPosition;
    master.publish('order', { orderId: 'o3', orderUpdateId: 0,
      nodes: [node('c', 0, true, here.x, here.y), node('e', 2, true, 1.5, 1.0), node('f', 4, false, 1.0, 1.5)],
      edges: [edge('c', 'e', 1, true), edge('e', 'f', 3, false)] });
    await master.waitFor('state', (s) => s.orderId === 'o3' && s.driving, 10000, 'driving o3');
    await broker.stop();
    await sleep(2000);
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

  test('startCharging docks, stopCharging backs off', async () => {
    master.instant('startCharging', 'ch1');
    await master.waitFor('state', (s) => action(s, 'ch1') === 'RUNNING', 5000, 'docking');
    const charging = await master.waitFor('state', (s) => action(s, 'ch1') === 'FINISHED' &&
      s.batteryState.charging, 120000, 'docked and charging');
    assert.ok(near(charging, 5.2, 1.5, 0.05), JSON.stringify(charging.agvPosition));
    master.instant('stopCharging', 'ch2');
    const off = await master.waitFor('state', (s) => action(s, 'ch2') === 'FINISHED', 30000, 'undocked');
    assert.ok(!near(off, 5.2, 1.5, 0.3), JSON.stringify(off.agvPosition));
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
