// Webhooks in corridord: subscriptions kept in the database, the robot's events POSTed to real local HTTP and HTTPS
// servers with a valid HMAC-SHA256 signature, retried while the receiver is down or failing, refused answers not
// retried, pending deliveries kept across a restart, and bad subscriptions refused with a problem.
import assert from 'node:assert/strict';
import { createHmac } from 'node:crypto';
import { mkdtempSync, rmSync } from 'node:fs';
import { createServer } from 'node:http';
import { createServer as createHttpsServer } from 'node:https';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  getJson, makeCertificate, openApiValidator, postJson, sendJson, sleep, startDaemon, waitFor, writeRoom,
} from './daemon.mjs';

const api = openApiValidator();
const dir = mkdtempSync(join(tmpdir(), 'corridor-webhooks-'));
const room = writeRoom(dir, 6, 3);
after(() => rmSync(dir, { recursive: true, force: true }));

// `untrusted` is one the daemon does not trust.
const trusted = makeCertificate(dir, 'trusted');
const untrusted = makeCertificate(dir, 'untrusted');

// A receiver: records each POST (headers and raw body) and answers with the next of `answers` (then 200).
async function startReceiver({ port = 0, tls = null, answers = [] } = {}) {
  const received = [];
  const handler = (req, res) => {
    let body = '';
    req.setEncoding('utf8');
    req.on('data', (d) => { body += d; });
    req.on('end', () => {
      received.push({ method: req.method, url: req.url, headers: req.headers, body });
      res.statusCode = answers.length ? answers.shift() : 200;
      res.end();
    });
  };
  const server = tls ? createHttpsServer({ key: tls.key, cert: tls.cert }, handler) : createServer(handler);
  await new Promise((resolve) => server.listen(port, '127.0.0.1', resolve));
  return {
    port: server.address().port,
    received,
    close: () => new Promise((resolve) => { server.close(resolve); server.closeAllConnections(); }),
  };
}

// A port nothing listens on (bound a moment, then released).
async function freePort() {
  const r = await startReceiver();
  await r.close();
  return r.port;
}

function checkSignature(delivery, secret) {
  const expected = `sha256=${createHmac('sha256', secret).update(delivery.body).digest('hex')}`;
  assert.equal(delivery.headers['x-corridor-signature'], expected, 'signed with the webhook secret');
}

async function subscribe(url, body) {
  const res = await postJson(`${url}/api/v1/webhooks`, body);
  assert.equal(res.status, 201, JSON.stringify(res.body));
  api.check('WebhookCreated', res.body);
  return res.body;
}

async function deliveries(url, id) {
  const res = await getJson(`${url}/api/v1/webhooks/${id}/deliveries`);
  assert.equal(res.status, 200);
  api.check('WebhookDeliveries', res.body);
  return res.body.deliveries;
}

const config = (stateTls) => `
sim:
  world: "${room}"
  start: {x_m: 1.0, y_m: 1.5, yaw_deg: 0}
  camera: {rate_hz: 15, width: 160, height: 120}
localization: {source: sim_truth}
perception: {detector: sim}
webhooks:
  timeout_s: 1
  first_retry_s: 0.3
  max_retry_s: 0.6
  max_attempts: 6
  ca_file: "${stateTls}"
  robot: test-robot
`;

describe('webhooks', () => {
  let daemon;
  before(async () => { daemon = await startDaemon({ config: config(trusted.certFile) }); });
  after(async () => { await daemon?.stop(); });

  test('subscriptions are listed, shown without their secret, deleted; bad ones get a problem', async () => {
    const made = await subscribe(daemon.url, { url: 'http://127.0.0.1:9/x', events: ['bump', 'lost', 'bump'],
      description: 'the lift' });
    assert.deepEqual(made.events, ['bump', 'lost']);
    assert.match(made.secret, /^[0-9a-f]{64}$/, 'a secret made by the robot, shown once');
    const one = await getJson(`${daemon.url}/api/v1/webhooks/${made.id}`);
    api.check('Webhook', one.body);
    assert.equal(one.body.secret, undefined);
    const list = await getJson(`${daemon.url}/api/v1/webhooks`);
    api.check('Webhooks', list.body);
    assert.ok(list.body.webhooks.some((w) => w.id === made.id));
    for (const body of [{}, { url: 'ftp://x/y', events: ['bump'] }, { url: 'http://127.0.0.1/', events: [] },
      { url: 'http://127.0.0.1/', events: ['party'] }, { url: 'http://127.0.0.1/', events: ['bump'], secret: 'short' },
      { url: 'http://127.0.0.1/', events: ['bump'], colour: 'red' }, [1]]) {
      const res = await postJson(`${daemon.url}/api/v1/webhooks`, body);
      assert.equal(res.status, 400, JSON.stringify(body));
      api.check('Problem', res.body);
    }
    assert.equal((await sendJson('DELETE', `${daemon.url}/api/v1/webhooks/${made.id}`)).status, 204);
    assert.equal((await getJson(`${daemon.url}/api/v1/webhooks/${made.id}`)).status, 404);
    assert.equal((await sendJson('DELETE', `${daemon.url}/api/v1/webhooks/${made.id}`)).status, 404);
  });

  test('a person pushed in by an external detector is delivered as person_detected, then person_left, signed',
    async () => {
      const receiver = await startReceiver();
      try {
        const secret = 'a-shared-secret-of-the-lift';
        const hook = await subscribe(daemon.url, { url: `http://127.0.0.1:${receiver.port}/robot?from=corridor`,
          events: ['person_detected', 'person_left'], secret });
        assert.equal(hook.secret, secret);
        const push = await postJson(`${daemon.url}/api/v1/detections`, { source: 'phone', ttl_s: 0.5,
          detections: [{ class: 'person', score: 0.9, position: { x: 1.5, y: 0.2, z: 0.9 } }] });
        assert.equal(push.status, 202, JSON.stringify(push.body));
        await waitFor(async () => receiver.received.length, (n) => n >= 2, 8000, 'person_detected and person_left');
        const [detected, left] = receiver.received;
        assert.equal(detected.method, 'POST');
        assert.equal(detected.url, '/robot?from=corridor');
        assert.equal(detected.headers['content-type'], 'application/json');
        assert.equal(detected.headers['x-corridor-event'], 'person_detected');
        checkSignature(detected, secret);
        checkSignature(left, secret);
        const body = JSON.parse(detected.body);
        api.check('WebhookPayload', body);
        assert.equal(body.type, 'person_detected');
        assert.equal(body.robot, 'test-robot');
        assert.equal(body.data.person.source, 'phone');
        assert.ok(Math.abs(body.data.person.position.x - 1.5) < 1e-6);
        assert.equal(JSON.parse(left.body).type, 'person_left');
        assert.equal(JSON.parse(left.body).data.person.track_id, body.data.person.track_id);
        // The deliveries, as the API shows them; and the events, as a system that polls sees them.
        const list = await deliveries(daemon.url, hook.id);
        assert.deepEqual(list.map((d) => [d.event, d.status, d.attempts, d.response_status]),
          [['person_left', 'delivered', 1, 200], ['person_detected', 'delivered', 1, 200]]);
        assert.equal(list[1].id, detected.headers['x-corridor-delivery']);
        const events = await getJson(`${daemon.url}/api/v1/events`);
        api.check('Events', events.body);
        const leaving = events.body.events.find((e) => e.type === 'person_left');
        assert.ok(leaving, JSON.stringify(events.body));
        // A poller asks for what came after the last one it saw.
        const later = await getJson(`${daemon.url}/api/v1/events?after=${leaving.sequence - 1}`);
        assert.equal(later.body.events[0].sequence, leaving.sequence, JSON.stringify(later.body));
        assert.ok(later.body.events.every((e) => e.sequence >= leaving.sequence));
        assert.equal((await getJson(`${daemon.url}/api/v1/events?after=x`)).status, 400);
        await sendJson('DELETE', `${daemon.url}/api/v1/webhooks/${hook.id}`);
      } finally {
        await receiver.close();
      }
    });

  test('a receiver that is down, then failing, gets the delivery once it is back; a refusal is not retried',
    async () => {
      const port = await freePort();
      const hook = await subscribe(daemon.url, { url: `http://127.0.0.1:${port}/hook`, events: ['bump'] });
      const ping = await postJson(`${daemon.url}/api/v1/webhooks/${hook.id}/ping`, {});
      assert.equal(ping.status, 202);
      // Nobody listens: attempts fail and are retried.
      await waitFor(async () => (await deliveries(daemon.url, hook.id))[0], (d) => d.attempts >= 2, 5000, 'retries');
      const waiting = (await deliveries(daemon.url, hook.id))[0];
      assert.equal(waiting.status, 'pending');
      assert.match(waiting.error, /cannot connect/);
      assert.equal(waiting.response_status, null);
      // Back, but answering 503 once: retried again, then delivered.
      const receiver = await startReceiver({ port, answers: [503] });
      try {
        const done = await waitFor(async () => (await deliveries(daemon.url, hook.id))[0],
          (d) => d.status !== 'pending', 8000, 'the delivery');
        assert.equal(done.status, 'delivered', JSON.stringify(done));
        assert.equal(done.id, ping.body.delivery);
        assert.ok(done.attempts >= 4, `attempts: ${done.attempts}`);
        assert.equal(receiver.received.length, 2);
        assert.equal(JSON.parse(receiver.received[1].body).type, 'ping');
        checkSignature(receiver.received[1], hook.secret);
        // A receiver that refuses (400): failed at once, not retried.
        receiver.received.length = 0;
        const refused = await startReceiver({ answers: [400] });
        await receiver.close();
        const other = await subscribe(daemon.url, { url: `http://127.0.0.1:${refused.port}/`, events: ['bump'] });
        await postJson(`${daemon.url}/api/v1/webhooks/${other.id}/ping`, {});
        const failed = await waitFor(async () => (await deliveries(daemon.url, other.id))[0],
          (d) => d.status !== 'pending', 5000, 'the refused delivery');
        assert.deepEqual([failed.status, failed.attempts, failed.response_status], ['failed', 1, 400]);
        await refused.close();
      } finally {
        await receiver.close();
      }
    });

  test('HTTPS: delivered to a receiver the robot trusts, failed for one it does not', async () => {
    const good = await startReceiver({ tls: trusted });
    const bad = await startReceiver({ tls: untrusted });
    try {
      const trustedHook = await subscribe(daemon.url, { url: `https://127.0.0.1:${good.port}/`, events: ['bump'] });
      const untrustedHook = await subscribe(daemon.url, { url: `https://127.0.0.1:${bad.port}/`, events: ['bump'] });
      await postJson(`${daemon.url}/api/v1/webhooks/${trustedHook.id}/ping`, {});
      await postJson(`${daemon.url}/api/v1/webhooks/${untrustedHook.id}/ping`, {});
      const ok = await waitFor(async () => (await deliveries(daemon.url, trustedHook.id))[0],
        (d) => d.status !== 'pending', 5000, 'the HTTPS delivery');
      assert.equal(ok.status, 'delivered', JSON.stringify(ok));
      checkSignature(good.received[0], trustedHook.secret);
      const refused = await waitFor(async () => (await deliveries(daemon.url, untrustedHook.id))[0],
        (d) => d.attempts >= 2, 5000, 'attempts at the untrusted receiver');
      assert.match(refused.error, /TLS handshake/);
      assert.equal(bad.received.length, 0, 'nothing sent to a receiver whose certificate is not trusted');
    } finally {
      await good.close();
      await bad.close();
    }
  });

  test('a mission reaching its goal is delivered as mission_succeeded, with its id', async () => {
    const receiver = await startReceiver();
    try {
      await subscribe(daemon.url, { url: `http://127.0.0.1:${receiver.port}/`,
        events: ['mission_succeeded', 'mission_failed'] });
      const pose = (await getJson(`${daemon.url}/api/v1/state`)).body.pose;
      const mission = await postJson(`${daemon.url}/api/v1/missions`,
        { waypoints: [{ x: Math.min(pose.x + 1.2, 4.5), y: 1.5 }] });
      assert.equal(mission.status, 201, JSON.stringify(mission.body));
      await waitFor(async () => receiver.received.length, (n) => n >= 1, 30000, 'the mission event');
      const body = JSON.parse(receiver.received[0].body);
      assert.equal(body.type, 'mission_succeeded', receiver.received[0].body);
      assert.equal(body.data.mission_id, mission.body.id);
    } finally {
      await receiver.close();
    }
  });

  test('backing into a wall is delivered as a bump', async () => {
    const receiver = await startReceiver();
    try {
      const hook = await subscribe(daemon.url, { url: `http://127.0.0.1:${receiver.port}/`, events: ['bump'] });
      // The wall behind stands 0.95 m back; the camera looks forward, so only the bumper tells.
      const end = Date.now() + 6000;
      while (Date.now() < end && !receiver.received.some((r) => r.headers['x-corridor-event'] === 'bump')) {
        await postJson(`${daemon.url}/api/v1/teleop`, { linear_mps: -0.4, angular_rps: 0 });
        await sleep(100);
      }
      const bump = receiver.received.find((r) => r.headers['x-corridor-event'] === 'bump');
      assert.ok(bump, 'a bump was delivered');
      checkSignature(bump, hook.secret);
    } finally {
      await receiver.close();
    }
  });
});

test('deliveries still pending when corridord stops are sent after it starts again', async () => {
  const stateDir = mkdtempSync(join(tmpdir(), 'corridor-webhooks-state-'));
  try {
    const port = await freePort();
    let daemon = await startDaemon({ config: config(''), stateDir });
    const hook = await subscribe(daemon.url, { url: `http://127.0.0.1:${port}/`, events: ['bump'] });
    const ping = await postJson(`${daemon.url}/api/v1/webhooks/${hook.id}/ping`, {});
    await waitFor(async () => (await deliveries(daemon.url, hook.id))[0], (d) => d.attempts >= 1, 5000, 'an attempt');
    // An event recorded before the stop.
    await postJson(`${daemon.url}/api/v1/detections`, { source: 'phone', ttl_s: 0.3,
      detections: [{ class: 'person', score: 0.9, position: { x: 1.5, y: 0, z: 0.9 } }] });
    const seen = (await waitFor(async () => (await getJson(`${daemon.url}/api/v1/events`)).body.events,
      (events) => events.some((e) => e.type === 'person_detected'), 5000, 'the event'))
      .find((e) => e.type === 'person_detected');
    await daemon.stop();
    const receiver = await startReceiver({ port });
    try {
      daemon = await startDaemon({ config: config(''), stateDir });
      const done = await waitFor(async () => (await deliveries(daemon.url, hook.id))[0],
        (d) => d.status === 'delivered', 5000, 'the delivery after the restart');
      assert.equal(done.id, ping.body.delivery);
      assert.equal(receiver.received.length, 1);
      // The events from before the restart are still there, under the same numbers.
      const events = (await getJson(`${daemon.url}/api/v1/events`)).body.events;
      assert.deepEqual(events.find((e) => e.sequence === seen.sequence), seen);
      await daemon.stop();
    } finally {
      await receiver.close();
    }
  } finally {
    rmSync(stateDir, { recursive: true, force: true });
  }
});
