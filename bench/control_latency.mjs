// Measures the control loop's answer to the depth camera in the running daemon: from a depth frame's arrival to the
// base command that drives on it (the target: <= 5 ms at the 99th percentile), while a mission drives the
// default world (Willow Garage) to a room 13 m away by its path and back, with the simulator rendering on the same two cores.
//   node bench/control_latency.mjs [--console]
// --console: with a console's load as well (a stream client and the depth view fetched five times a second).
import { require, getJson, postJson, sleep, startDaemon } from '../tests/daemon.mjs';

const withConsole = process.argv.includes('--console');
const daemon = await startDaemon();
let ws = null;
let camera = null;
if (withConsole) {
  const WebSocket = require('ws');
  ws = new WebSocket(`${daemon.url.replace('http', 'ws')}/api/v1/stream`);
  camera = setInterval(() => fetch(`${daemon.url}/api/v1/camera/depth?colormap=true`).then((r) => r.arrayBuffer()), 200);
}
await sleep(1000);
const start = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: 24.0, y: 27.0 }, { x: 24.38, y: 24.07 }] });
if (start.status !== 201) throw new Error(JSON.stringify(start.body));
let state;
const rates = [];
for (;;) {
  await sleep(1000);
  state = (await getJson(`${daemon.url}/api/v1/state`)).body;
  if (state.control_latency?.rate_hz > 0) rates.push(state.control_latency.rate_hz);
  if (state.mission.status !== 'active') break;
}
ws?.close();
clearInterval(camera);
await daemon.stop();
const l = state.control_latency;
const mean = rates.reduce((a, b) => a + b, 0) / Math.max(rates.length, 1);
console.log(`mission ${state.mission.status}; ${l.samples} frame-driven commands at ${mean.toFixed(1)} Hz on average`);
console.log(`frame arrival to base command over the last ${Math.min(l.samples, 1000)}: p50 ${l.p50_ms.toFixed(3)} ms, ` +
            `p99 ${l.p99_ms.toFixed(3)} ms, max ${l.max_ms.toFixed(3)} ms`);
