// A long run under a console crowd's load: corridord drives missions back and forth across a 12 x 8 m room with
// pillars and three walking people while 20 stream clients take what the console takes (state, the ground lanes,
// detections) and HTTP clients poll the state, the laser scan, the depth view and the map as the console does. Every
// 10 s it samples the daemon's resident memory and the control loop's frame-to-command latency; at the end it prints
// the largest of each (issue 38's targets: resident at most 150 MB, p99 at most 1 ms).
//   node bench/soak.mjs [--minutes N] [--clients N]
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import {
  apiFetch, authHeaders, getJson, pillarRoom, postJson, require, sleep, startDaemon, waitFor,
} from '../tests/daemon.mjs';

function option(name, fallback) {
  const i = process.argv.indexOf(name);
  return i >= 0 ? Number(process.argv[i + 1]) : fallback;
}
const minutes = option('--minutes', 15);
const clients = option('--clients', 20);
if (!(minutes > 0) || !Number.isInteger(clients) || clients < 0) throw new Error('--minutes > 0, --clients >= 0');

const dir = mkdtempSync(join(tmpdir(), 'corridor-bench-'));
const daemon = await startDaemon({ config: pillarRoom(dir) });
const memoryMb = (key) => Number(new RegExp(`${key}:\\s+(\\d+) kB`).exec(
  readFileSync(`/proc/${daemon.pid}/status`, 'utf8'))[1]) / 1024;

const WebSocket = require('ws');
const sockets = [];
let streamed = 0;
const timers = [];
let requests = 0;
let failures = 0;
// `path` fetched every `ms` by one client, never two at once.
const poll = (path, ms) => {
  let busy = false;
  timers.push(setInterval(() => {
    if (busy) return;
    busy = true;
    apiFetch(`${daemon.url}${path}`).then((r) => {
      requests += 1;
      if (!r.ok) failures += 1;
      return r.arrayBuffer();
    }).catch(() => { failures += 1; }).finally(() => { busy = false; });
  }, ms));
};

try {
  await waitFor(() => getJson(`${daemon.url}/api/v1/state`), (r) => r.body?.pose !== null, 20000, 'a pose');
  for (let i = 0; i < clients; ++i) {
    const ws = new WebSocket(`${daemon.url.replace('http', 'ws')}/api/v1/stream`, { headers: authHeaders(daemon.url) });
    ws.on('open', () => ws.send(JSON.stringify(
      { type: 'subscribe', topics: ['state', 'ground/lanes', 'perception/detections'] })));
    ws.on('message', () => { streamed += 1; });
    sockets.push(ws);
  }
  poll('/api/v1/state', 100);
  poll('/api/v1/laser/scan', 200);
  poll('/api/v1/camera/depth?colormap=true', 200);
  poll('/api/v1/map', 5000);
  poll('/api/v1/map/image', 5000);
  poll('/api/v1/events', 2000);

  const legs = [[{ x: 11.0, y: 4.0 }], [{ x: 1.0, y: 4.0 }]];
  let missions = 0;
  let failed = 0;
  let mission = null;
  const samples = [];
  const end = Date.now() + minutes * 60000;
  let nextSample = Date.now() + 10000;
  while (Date.now() < end) {
    const state = (await getJson(`${daemon.url}/api/v1/state`)).body;
    if (!mission || state.mission?.id !== mission || state.mission.status !== 'active') {
      if (mission && state.mission?.status === 'failed') failed += 1;
      const start = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: legs[missions % 2] });
      if (start.status !== 201) throw new Error(`a mission was refused: ${JSON.stringify(start.body)}`);
      mission = start.body.id;
      missions += 1;
    }
    if (Date.now() >= nextSample) {
      nextSample += 10000;
      const l = state.control_latency;
      samples.push({ rss: memoryMb('VmRSS'), p99: l.p99_ms, max: l.max_ms });
      const s = samples.at(-1);
      console.log(`${(samples.length * 10).toString().padStart(4)} s: resident ${s.rss.toFixed(0)} MB, ` +
                  `frame to command p99 ${s.p99.toFixed(2)} ms (max ${s.max.toFixed(2)}), ${missions} missions`);
    }
    await sleep(500);
  }
  const worst = (key) => Math.max(...samples.map((s) => s[key]));
  const sorted = samples.map((s) => s.p99).sort((a, b) => a - b);
  console.log(`${minutes} min, ${clients} stream clients (${streamed} messages), ${requests} requests ` +
              `(${failures} failed), ${missions} missions (${failed} failed)`);
  console.log(`resident: largest ${worst('rss').toFixed(0)} MB, last ${samples.at(-1).rss.toFixed(0)} MB, ` +
              `peak (VmHWM) ${memoryMb('VmHWM').toFixed(0)} MB`);
  console.log(`frame to command p99 over the last 1000 frames, sampled every 10 s: median ` +
              `${sorted[Math.floor(sorted.length / 2)].toFixed(2)} ms, largest ${worst('p99').toFixed(2)} ms; ` +
              `largest single ${worst('max').toFixed(2)} ms`);
} finally {
  for (const t of timers) clearInterval(t);
  for (const ws of sockets) ws.close();
  await daemon.stop();
  rmSync(dir, { recursive: true, force: true });
}
