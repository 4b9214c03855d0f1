// Measures corridord's CPU while idle with the simulator, per thread. Executor threads carry their names
// (control, mapping, planning, perception, io, sim), so the simulator's own work (physics and ray-cast sensors,
// all on "sim") separates from the rest of the daemon.
//   node bench/idle_cpu.mjs [seconds=30] [--console]
// --console: what an open console costs: a stream client, and the camera view fetched five times a second.
import { execFileSync } from 'node:child_process';

import {
  apiFetch, authHeaders, nsByName, require, sleep, startDaemon, threadCpu,
} from '../tests/daemon.mjs';

const seconds = Number(process.argv.find((a) => /^\d+$/.test(a)) ?? 30);
const withConsole = process.argv.includes('--console');

const daemon = await startDaemon();
const pid = Number(execFileSync('pgrep', ['-n', 'corridord']).toString());
let ws = null;
let camera = null;
if (withConsole) {
  const WebSocket = require('ws');
  ws = new WebSocket(`${daemon.url.replace('http', 'ws')}/api/v1/stream`, { headers: authHeaders(daemon.url) });
  const view = `${daemon.url}/api/v1/camera/depth?colormap=true`;
  camera = setInterval(() => apiFetch(view).then((r) => r.arrayBuffer()), 200);
}
await sleep(3000);  // start-up and the first frames are not idle
const before = threadCpu(pid);
await sleep(seconds * 1000);
const after = threadCpu(pid);
ws?.close();
clearInterval(camera);
await daemon.stop();

const byName = nsByName(before, after);
const percent = (ns) => (100 * ns) / 1e9 / seconds;
const total = [...byName.values()].reduce((a, b) => a + b, 0);
const sim = byName.get('sim') ?? 0;
console.log(`corridord idle for ${seconds} s${withConsole ? ' with a console connected' : ''}:`);
for (const [name, ns] of [...byName].sort((a, b) => b[1] - a[1])) {
  console.log(`  ${name.padEnd(16)} ${percent(ns).toFixed(1).padStart(5)} % of one core`);
}
console.log(`  total            ${percent(total).toFixed(1).padStart(5)} %`);
console.log(`  beyond the sim   ${percent(total - sim).toFixed(1).padStart(5)} %`);
