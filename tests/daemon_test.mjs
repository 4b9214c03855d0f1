// corridord with the simulator, over real HTTP and WebSocket: what a console or a building system sees.
import assert from 'node:assert/strict';
import { after, before, describe, test } from 'node:test';

import {
  apiFetch, authHeaders, driveUntil, getJson, openApiValidator, postJson, require, runCorridord, sourceDir,
  startDaemon, waitFor,
} from './daemon.mjs';

const WebSocket = require('ws');
const api = openApiValidator();

function distance(a, b) {
  return Math.hypot(a.x - b.x, a.y - b.y);
}

async function state(url) {
  const { status, body } = await getJson(`${url}/api/v1/state`);
  assert.equal(status, 200);
  api.check('State', body);
  return body;
}

async function expectProblem(responsePromise, status) {
  const res = await responsePromise;
  assert.equal(res.status, status, JSON.stringify(res.body));
  assert.equal(res.type, 'application/problem+json');
  api.check('Problem', res.body);
  assert.equal(res.body.status, status);
  return res.body;
}

// Opens the stream and collects its messages.
async function openStream(url) {
  const ws = new WebSocket(`${url.replace('http', 'ws')}/api/v1/stream`, { headers: authHeaders(url) });
  const messages = [];
  ws.on('message', (data) => messages.push({ at: Date.now(), message: JSON.parse(String(data)) }));
  await new Promise((resolve, reject) => { ws.once('open', resolve); ws.once('error', reject); });
  return { ws, messages };
}

// Subscribes the stream `ws` (its messages collected in `messages`) to `topics` and waits for the reply.
async function subscribed(ws, messages, topics) {
  const count = messages.length;
  ws.send(JSON.stringify({ type: 'subscribe', topics }));
  await waitFor(() => messages.slice(count), (m) => m.some((x) => x.message.type === 'subscribed'), 5000, 'subscribed');
}

describe('corridord in the Willow Garage building', () => {
  let daemon;
  before(async () => { daemon = await startDaemon(); });
  after(async () => { await daemon?.stop(); });

  test('health, state, map and topics match the OpenAPI contract', async () => {
    const health = await getJson(`${daemon.url}/api/v1/health`);
    assert.equal(health.status, 200);
    api.check('Health', health.body);

    // Every node up and looping (explore waits for mapping).
    const s = await waitFor(() => state(daemon.url), (x) => x.nodes.every((n) => n.health === 'ok' &&
      (n.name === 'explore' || n.rate_hz > 0)), 5000, 'every node ok and looping');
    assert.deepEqual(s.nodes.map((n) => n.name).sort(), ['charging', 'control', 'devices', 'events', 'explore', 'face',
      'ground', 'localization', 'mission', 'octree', 'perception', 'sim', 'tracking']);
    assert.equal(s.face, 'neutral');
    for (const node of s.nodes) {
      assert.equal(node.health, 'ok', `${node.name}: ${node.message}`);
      if (node.name !== 'explore') assert.ok(node.rate_hz > 0, `${node.name} loops`);  // it waits for mapping
    }
    assert.ok(Math.abs(s.pose.x - 24.38) < 0.01 && Math.abs(s.pose.y - 24.07) < 0.01, JSON.stringify(s.pose));

    const map = await getJson(`${daemon.url}/api/v1/map`);
    api.check('MapInfo', map.body);
    assert.equal(map.body.width, 1165);
    assert.equal(map.body.height, 945);
    const image = await apiFetch(`${daemon.url}${map.body.image_url}`);
    assert.equal(image.headers.get('content-type'), 'image/png');
    const png = Buffer.from(await image.arrayBuffer());
    assert.equal(png.readUInt32BE(16), 1165);  // IHDR width
    assert.equal(png.readUInt32BE(20), 945);

    // Nobody walks in the default world: no traffic overlay, and a problem that says so.
    const traffic = await expectProblem(getJson(`${daemon.url}/api/v1/map/traffic`), 404);
    assert.match(traffic.detail, /nobody has been seen walking/);

    const topics = await getJson(`${daemon.url}/api/v1/topics`);
    api.check('Topics', topics.body);
    for (const t of ['odom', 'pose', 'cmd_vel', 'camera/rgbd', 'scan', 'ground/lanes']) assert.ok(topics.body.topics.includes(t), t);

    const doc = await getJson(`${daemon.url}/api/v1/openapi.json`);
    assert.equal(doc.body.openapi, '3.1.0');
    assert.deepEqual(doc.body, api.doc, 'the daemon serves the document in the tree');
    // One version: CMake's, which the daemon reports; the contract says the same.
    assert.equal(doc.body.info.version, health.body.version);
  });

  test('teleop moves the robot and the deadman stops it', async () => {
    const before = await state(daemon.url);
    const accepted = await postJson(`${daemon.url}/api/v1/teleop`, { linear_mps: 0.4, angular_rps: 0 });
    assert.equal(accepted.status, 200);
    api.check('TeleopAccepted', accepted.body);
    assert.equal(accepted.body.expires_in_s, 0.5);
    // The robot faces +y (yaw 90 degrees) down a free corridor.
    const moving = await driveUntil(daemon.url, { linear_mps: 0.4, angular_rps: 0 },
      (x) => x.velocity.linear_mps > 0.3 && x.sim_true_pose.y - before.sim_true_pose.y > 0.3, 5000, 'moving forward');
    assert.equal(moving.mode, 'teleop');

    // No more commands: the deadman (0.5 s) runs out and the robot brakes to a stop, and stays there.
    const stopped = await waitFor(() => state(daemon.url), (x) => x.mode === 'idle' && x.velocity.linear_mps === 0,
      5000, 'stopped by the deadman');
    const later = await waitFor(() => state(daemon.url), (x) => x.stamp_s > stopped.stamp_s + 0.5, 5000,
      'half a second later');
    assert.ok(distance(later.sim_true_pose, stopped.sim_true_pose) < 1e-6, 'stays still');
  });

  test('the stream pushes state at 10 Hz or more and accepts teleop', async () => {
    const { ws, messages } = await openStream(daemon.url);
    const states = await waitFor(() => messages.filter((m) => m.message.topic === 'state'), (x) => x.length >= 11,
      5000, 'eleven state messages');
    // Ten intervals by the daemon's own clock: 10 Hz or more (5 % for the timer's wake-ups).
    const span = states[10].message.data.stamp_s - states[0].message.data.stamp_s;
    assert.ok(span <= 1.05, `ten state intervals took ${span} s`);
    api.check('State', states.at(-1).message.data);

    const start = states.at(-1).message.data.sim_true_pose;
    let sent = 0;
    const timer = setInterval(() => {
      ws.send(JSON.stringify({ type: 'teleop', linear_mps: 0, angular_rps: 1.0 }));
      ++sent;
    }, 100);
    try {
      await waitFor(() => state(daemon.url), (x) => Math.abs(x.sim_true_pose.yaw - start.yaw) > 0.5, 5000,
        `turned half a radian from ${start.yaw}`);
    } finally {
      clearInterval(timer);
    }
    // Every command acknowledged.
    await waitFor(() => messages.filter((m) => m.message.type === 'teleop_ack'), (acks) => acks.length === sent, 5000,
      'an acknowledgement of each teleop message');
    await waitFor(() => state(daemon.url), (x) => x.mode === 'idle', 5000, 'the turn ended by the deadman');

    // Bad messages get an error reply and the stream stays open.
    ws.send('not json');
    ws.send(JSON.stringify({ type: 'teleop', linear_mps: 'fast', angular_rps: 0 }));
    ws.send(JSON.stringify({ type: 'subscribe', topics: ['no/such/topic'] }));
    // Replies come in order: once a good message's is here, so is every bad one's, and there is no fourth.
    await subscribed(ws, messages, ['state']);
    assert.equal(messages.filter((m) => m.message.type === 'error').length, 3);
    assert.equal(ws.readyState, WebSocket.OPEN);

    // Subscribing to a bus topic by name streams it.
    ws.send(JSON.stringify({ type: 'subscribe', topics: ['odom', 'ground/lanes'] }));
    await waitFor(() => messages, (all) => all.filter((m) => m.message.topic === 'odom').length >= 3 &&
      all.filter((m) => m.message.topic === 'ground/lanes').length >= 3, 5000, 'odom and lanes streamed');
    const odom = messages.filter((m) => m.message.topic === 'odom');
    assert.ok('bumper_pressed' in odom.at(-1).message.data);
    const lanes = messages.filter((m) => m.message.topic === 'ground/lanes');
    assert.ok(lanes.length >= 3);
    api.check('GroundLanes', lanes.at(-1).message.data);
    assert.equal(lanes.at(-1).message.data.lanes.length, 10);
    ws.close();
  });

  test('camera snapshots: 16-bit depth PNG, false-colour PNG and colour JPEG', async () => {
    const depth = await apiFetch(`${daemon.url}/api/v1/camera/depth`);
    assert.equal(depth.status, 200);
    assert.equal(depth.headers.get('content-type'), 'image/png');
    const png = Buffer.from(await depth.arrayBuffer());
    assert.equal(png.readUInt32BE(16), 320);
    assert.equal(png.readUInt32BE(20), 240);
    assert.equal(png[24], 16, 'bit depth');
    const view = await apiFetch(`${daemon.url}/api/v1/camera/depth?colormap=true`);
    assert.equal(Buffer.from(await view.arrayBuffer())[24], 8);
    const color = await apiFetch(`${daemon.url}/api/v1/camera/color`);
    assert.equal(color.headers.get('content-type'), 'image/jpeg');
    const jpeg = Buffer.from(await color.arrayBuffer());
    assert.equal(jpeg.readUInt16BE(0), 0xffd8);
  });

  test('malformed, oversized and wrongly typed requests get a 4xx and the daemon keeps running', async () => {
    const url = `${daemon.url}/api/v1/teleop`;
    await expectProblem(postJson(url, '{"linear_mps": 0.2,'), 400);
    await expectProblem(postJson(url, { linear_mps: 'fast', angular_rps: 0 }), 400);
    await expectProblem(postJson(url, { linear_mps: 0.2 }), 400);
    await expectProblem(postJson(url, { linear_mps: 0.2, angular_rps: 0, turbo: true }), 400);
    await expectProblem(postJson(url, [1, 2]), 400);
    await expectProblem(postJson(url, 'linear_mps=0.2', 'application/x-www-form-urlencoded'), 415);
    await expectProblem(postJson(url, JSON.stringify({ pad: 'x'.repeat(5_000_000) })), 413);
    await expectProblem(getJson(`${daemon.url}/api/v1/no-such-route`), 404);
    await expectProblem(getJson(`${daemon.url}/api/v1/teleop`), 405);
    await expectProblem(postJson(`${daemon.url}/api/v1/state`, {}), 405);
    await expectProblem(getJson(`${daemon.url}/api/v1/stream`), 426);
    await expectProblem(getJson(`${daemon.url}/../../etc/passwd`), 404);
    // A request that is not HTTP at all.
    const net = await import('node:net');
    const reply = await new Promise((resolve) => {
      const socket = net.connect(daemon.port, '127.0.0.1', () => socket.end('GARBAGE\r\n\r\n'));
      let data = '';
      socket.on('data', (d) => { data += d; });
      socket.on('close', () => resolve(data));
    });
    assert.match(reply, /^HTTP\/1\.1 400/);
    // Nothing of that moved the robot, and the daemon is healthy.
    const s = await state(daemon.url);
    assert.notEqual(s.mode, 'teleop');
    assert.equal((await getJson(`${daemon.url}/api/v1/health`)).status, 200);
  });

  test('stream messages of any shape get an error reply; other clients and the daemon go on', async () => {
    const bystander = await openStream(daemon.url);
    const { ws, messages } = await openStream(daemon.url);
    const bad = ['{"type":1}', '{"type":null}', '{"type":[]}', '{"type":{"a":1}}', '[]', '"subscribe"', '{}',
      '{"type":"subscribe"}', '{"type":"subscribe","topics":"state"}', '{"type":"subscribe","topics":[1,null]}',
      '{"type":"teleop","linear_mps":1e400,"angular_rps":0}', '{"type":"teleop","linear_mps":null,"angular_rps":0}',
      '{"type":"teleop","linear_mps":0,"angular_rps":0,"extra":{}}', '\u0000\u00ff', '{"type":"\ud800"}'];
    for (const text of bad) ws.send(text);
    // Replies come in order: once a good message's is here, so is every bad one's.
    await subscribed(ws, messages, ['state']);
    const errors = messages.filter((m) => m.message.type === 'error');
    assert.equal(errors.length, bad.length, JSON.stringify(errors.map((e) => e.message.detail)));
    for (const e of errors) assert.ok(e.message.status >= 400 && e.message.status < 500, JSON.stringify(e.message));
    assert.equal(ws.readyState, WebSocket.OPEN);
    // The other client still gets its state, and every node is as healthy as before.
    const before = bystander.messages.length;
    await waitFor(() => bystander.messages.length, (n) => n > before, 5000, 'the other client still served');
    const s = await state(daemon.url);
    for (const node of s.nodes) assert.notEqual(node.health, 'error', `${node.name}: ${node.message}`);
    assert.equal((await getJson(`${daemon.url}/api/v1/health`)).status, 200);
    ws.close();
    bystander.ws.close();
  });

  test('an app shows an expression and makes the robot say something; bad requests get a problem', async () => {
    const before = await getJson(`${daemon.url}/api/v1/face`);
    assert.equal(before.status, 200);
    api.check('Face', before.body);
    const res = await postJson(`${daemon.url}/api/v1/face`, { expression: 'happy', hold_s: 30, say: 'Welcome to the lab' });
    assert.equal(res.status, 202, JSON.stringify(res.body));
    api.check('FaceAccepted', res.body);
    const face = await waitFor(async () => (await getJson(`${daemon.url}/api/v1/face`)).body,
      (f) => f.expression === 'happy' && f.said_sequence > before.body.said_sequence, 5000, 'the face happy and speaking');
    api.check('Face', face);
    assert.equal(face.expression, 'happy');
    assert.equal(face.said, 'Welcome to the lab');
    assert.equal(face.said_kind, 'request');
    // The state takes the expression from the face's topic, published on the face node's next tick.
    await waitFor(() => state(daemon.url), (s) => s.face === 'happy', 2000, "the state's face happy");
    // The phrase was said aloud: its audio, a WAV the face page plays.
    const speech = await apiFetch(`${daemon.url}/api/v1/face/speech/${face.said_sequence}`);
    assert.equal(speech.status, 200);
    assert.equal(speech.headers.get('content-type'), 'audio/wav');
    const wav = Buffer.from(await speech.arrayBuffer());
    assert.equal(wav.toString('ascii', 0, 4), 'RIFF');
    assert.equal(wav.toString('ascii', 8, 12), 'WAVE');
    assert.ok(wav.length > 44 + 22050 * 2 * 0.5, `about a second of speech, got ${wav.length} bytes`);
    await expectProblem(getJson(`${daemon.url}/api/v1/face/speech/${face.said_sequence + 1000}`), 404);
    await expectProblem(getJson(`${daemon.url}/api/v1/face/speech/-1`), 400);
    for (const body of [{}, { expression: 'grumpy' }, { expression: 'happy', hold_s: -1 }, { hold_s: 2 },
      { say: '' }, { say: 'x'.repeat(201) }, { expression: 'sad', colour: 'blue' }, [1, 2]]) {
      await expectProblem(postJson(`${daemon.url}/api/v1/face`, body), 400);
    }
    await expectProblem(postJson(`${daemon.url}/api/v1/face`, '{"say": ', 'application/json'), 400);
  });

  test('the console is served at /', async () => {
    const res = await apiFetch(`${daemon.url}/`);
    assert.equal(res.status, 200);
    assert.match(res.headers.get('content-type'), /text\/html/);
    assert.match(await res.text(), /corridor console/);
  });
});

describe('corridord in a small arena', () => {
  const config = `
sim:
  world: "${sourceDir}tests/data/maps/lse_arena/lse_arena.yaml"
  start: {x_m: 1.0, y_m: 0.75, yaw_deg: 0}
  camera: {rate_hz: 15, width: 160, height: 120}
`;

  test('driving at a wall it sees, the robot slows and stops short of it', async () => {
    const daemon = await startDaemon({ config });
    try {
      // The outer wall stands 2.95 m ahead; ask for full speed at it until the robot stands still.
      let bumped = false;
      let slowed = false;
      const s = await driveUntil(daemon.url, { linear_mps: 0.5, angular_rps: 0 }, (x) => {
        bumped ||= x.bumper_pressed;
        slowed ||= x.stop_reason === 'slowed for an obstacle ahead';
        return bumped || (x.sim_true_pose.x > 2.0 && Math.abs(x.velocity.linear_mps) < 0.005);
      }, 15000, 'standing still before the wall');
      const front = s.sim_true_pose.x + 0.2;
      assert.ok(!bumped, 'never touched the wall');
      assert.ok(slowed, 'the control loop said why it slowed');
      assert.ok(front < 3.95 && front > 3.95 - 0.4, `stopped with its front at x = ${front}, the wall at 3.95`);
    } finally {
      await daemon.stop();
    }
  });

  test('backing into a wall it cannot see, it stops against it instead of passing through', async () => {
    const daemon = await startDaemon({ config });
    try {
      // The wall behind stands 0.95 m back (x = 0.05); the camera looks forward, so only the bumper tells.
      let bumped = false;
      let surprised = false;
      await driveUntil(daemon.url, { linear_mps: -0.4, angular_rps: 0 }, (x) => {
        // Pressed for a moment: the control node then holds the robot from backing on for a second, and says why.
        bumped ||= x.bumper_pressed || x.stop_reason === 'bumper pressed: not backing';
        surprised ||= x.face === 'surprised';
        assert.ok(x.sim_true_pose.x - 0.2 >= 0.05 - 1e-6, `inside the wall at x = ${x.sim_true_pose.x}`);
        return bumped && surprised;
      }, 8000, 'bumped, and surprised');
      assert.ok(bumped, 'the bumper reported the contact');
      assert.ok(surprised, 'the face showed surprise at the bump');
      const s = await state(daemon.url);
      assert.ok(s.sim_true_pose.x - 0.2 < 0.05 + 0.1, `reached the wall: x = ${s.sim_true_pose.x}`);
    } finally {
      await daemon.stop();
    }
  });

  test('SIGTERM stops the robot first and exits cleanly', async () => {
    const daemon = await startDaemon({ config });
    await postJson(`${daemon.url}/api/v1/teleop`, { linear_mps: 0.3, angular_rps: 0 });
    const { code } = await daemon.stop();
    assert.equal(code, 0);
    const log = daemon.log();
    assert.match(log, /stopping the robot/);
    const controlStopped = log.indexOf('control: inactive');
    const simStopped = log.indexOf('sim: inactive');
    assert.ok(controlStopped > 0 && simStopped > controlStopped, 'control stops before the simulator');
    assert.match(log, /stopped$/m);
  });
});

describe('corridord start-up', () => {
  test('--help and --version', async () => {
    const help = await runCorridord(['--help']);
    assert.equal(help.code, 0);
    for (const flag of ['--config', '--port', '--state-dir', '--map', '--world']) assert.match(help.stdout, new RegExp(flag));
    const version = await runCorridord(['--version']);
    assert.match(version.stdout, /^corridord \d+\.\d+\.\d+/);
    const bad = await runCorridord(['--frobnicate']);
    assert.equal(bad.code, 2);
    assert.match(bad.stderr, /unknown option --frobnicate/);
  });

  test('a broken configuration stops start-up with the key path', async () => {
    const { mkdtempSync, writeFileSync } = await import('node:fs');
    const { join } = await import('node:path');
    const dir = mkdtempSync(join((await import('node:os')).tmpdir(), 'corridor-cfg-'));
    const cases = [
      ['sim: {world: x.yaml, camera: {widht: 3}}\n', /sim\.camera\.widht: unknown key/],
      ['server: {port: -4}\nsim: {world: x.yaml}\n', /server\.port: must be between 0 and 65535/],
      ['sim: {world: missing.yaml}\n', /missing\.yaml.*does not exist/],
    ];
    for (const [text, expected] of cases) {
      writeFileSync(join(dir, 'c.yaml'), text);
      const run = await runCorridord(['--config', join(dir, 'c.yaml'), '--state-dir', dir]);
      assert.equal(run.code, 1, run.stderr);
      assert.match(run.stderr, expected);
    }
    const port = await runCorridord(['--port', '99999', '--state-dir', dir]);
    assert.equal(port.code, 1);
    assert.match(port.stderr, /server\.port/);
    const world = await runCorridord(['--world', join(sourceDir, 'README.md'), '--state-dir', dir]);
    assert.equal(world.code, 1);
    assert.match(world.stderr, /README\.md/);
  });

  test('--world loads the 3D small house and --map its SLAM map', async () => {
    const daemon = await startDaemon({
      args: ['--world', `${sourceDir}config/worlds/small_house/worlds/small_house.world`,
        '--map', `${sourceDir}config/worlds/small_house/maps/map.yaml`],
      config: 'sim:\n  world: unused.yaml\n  start: {x_m: -3.5, y_m: 1.0, yaw_deg: 270}\n',
    });
    try {
      const map = await getJson(`${daemon.url}/api/v1/map`);
      assert.equal(map.body.name, 'map');
      // A depth image once the camera has seen the house.
      await waitFor(async () => (await apiFetch(`${daemon.url}/api/v1/camera/depth`)).status, (status) => status === 200,
        5000, 'a depth image');
    } finally {
      await daemon.stop();
    }
  });
});
