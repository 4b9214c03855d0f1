// GET /api/v1/state under load: requests a second with 16 keep-alive connections on loopback (wrk, one thread),
// against GET /api/v1/health in the same run as the baseline (the HTTP server, authentication and routing with
// nothing to make), while the simulated robot drives a mission; then the daemon's resident memory.
//   node bench/state_load.mjs [--seconds N]
import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import { authHeaders, getJson, postJson, startDaemon, waitFor, writeRoom } from '../tests/daemon.mjs';

const at = process.argv.indexOf('--seconds');
const seconds = at > 0 ? Number(process.argv[at + 1]) : 10;
const dir = mkdtempSync(join(tmpdir(), 'corridor-bench-'));
const daemon = await startDaemon({ config: `
sim:
  world: "${writeRoom(dir, 12, 8)}"
  start: {x_m: 1.0, y_m: 4.0, yaw_deg: 0}
  pedestrians: 2
` });
const memory = (key) => Number(new RegExp(`${key}:\\s+(\\d+) kB`).exec(
  readFileSync(`/proc/${daemon.pid}/status`, 'utf8'))[1]) / 1024;
try {
  await waitFor(() => getJson(`${daemon.url}/api/v1/state`), (r) => r.body?.pose !== null, 20000, 'a pose');
  const start = await postJson(`${daemon.url}/api/v1/missions`,
    { waypoints: [{ x: 11.0, y: 4.0 }, { x: 1.0, y: 4.0 }, { x: 11.0, y: 4.0 }, { x: 1.0, y: 4.0 }] });
  if (start.status !== 201) throw new Error(JSON.stringify(start.body));
  const [header, value] = Object.entries(authHeaders(daemon.url))[0];
  const load = (path) => {
    const out = spawnSync('wrk', ['-t1', '-c16', `-d${seconds}s`, '--latency', '-H', `${header}: ${value}`,
      `${daemon.url}${path}`], { encoding: 'utf8' });
    if (out.status !== 0) throw new Error(`wrk: ${out.stderr || out.error}`);
    const rate = Number(/Requests\/sec:\s+([\d.]+)/.exec(out.stdout)[1]);
    const p99 = /99%\s+(\S+)/.exec(out.stdout)[1];
    const errors = /Non-2xx or 3xx responses: (\d+)/.exec(out.stdout);
    if (errors) throw new Error(`${path}: ${errors[1]} responses were errors`);
    return { rate, p99 };
  };
  const health = load('/api/v1/health');
  const state = load('/api/v1/state');
  console.log(`GET /api/v1/health ${health.rate.toFixed(0)} req/s (p99 ${health.p99}), ` +
    `GET /api/v1/state ${state.rate.toFixed(0)} req/s (p99 ${state.p99}): ` +
    `${(state.rate / health.rate).toFixed(2)} of health's; ` +
    `resident ${memory('VmRSS').toFixed(0)} MB (peak ${memory('VmHWM').toFixed(0)} MB)`);
} finally {
  await daemon.stop();
  rmSync(dir, { recursive: true, force: true });
}
