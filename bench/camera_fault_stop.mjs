// Measures how fast the daemon stops the robot when its depth camera stops answering: a mission cruises across an
// empty 12 x 8 m room, the simulated camera is stopped (PUT /api/v1/sim/faults), and the state is polled every 10 ms
// for the first zero forward command and for standstill. Wall-clock times from the fault, trials alternating direction.
//   node bench/camera_fault_stop.mjs [TRIALS]      (default 20)
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import { getJson, postJson, sendJson, sleep, startDaemon, waitFor, writeRoom } from '../tests/daemon.mjs';

const dir = mkdtempSync(join(tmpdir(), 'corridor-bench-'));
const daemon = await startDaemon({ config: `
devices: {laser: {driver: none}}
sim:
  world: "${writeRoom(dir, 12, 8)}"
  start: {x_m: 1.0, y_m: 4.0, yaw_deg: 0}
` });
const state = async () => (await getJson(`${daemon.url}/api/v1/state`)).body;
const rows = [];
const trials = Number(process.argv[2] ?? 20);
for (let i = 0; i < trials; ++i) {
  const x = i % 2 === 0 ? 11.0 : 1.0;
  const res = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x, y: 4.0 }] });
  if (res.status !== 201) throw new Error(JSON.stringify(res.body));
  const cruising = await waitFor(state, (s) => Math.abs(s.velocity.linear_mps) > 0.45, 30000, 'cruising speed');
  await sendJson('PUT', `${daemon.url}/api/v1/sim/faults`, { camera_stopped: true });
  const t0 = performance.now();
  let commandZero = null;
  for (;;) {
    const s = await state();
    const t = performance.now() - t0;
    if (commandZero === null && s.command.linear_mps <= 0.0) commandZero = t;
    if (Math.abs(s.velocity.linear_mps) < 0.005) {
      rows.push({ trial: i + 1, speed: cruising.velocity.linear_mps, commandZero, standstill: t });
      break;
    }
    await sleep(10);
  }
  await sendJson('PUT', `${daemon.url}/api/v1/sim/faults`, { camera_stopped: false });
  await waitFor(state, (s) => s.mission.status !== 'active', 60000, 'the mission');
}
await daemon.stop();
rmSync(dir, { recursive: true, force: true });
for (const r of rows) {
  console.log(`trial ${r.trial}: from ${r.speed.toFixed(2)} m/s, forward command zero after ${r.commandZero.toFixed(0)} ms, ` +
              `standstill after ${r.standstill.toFixed(0)} ms`);
}
const zero = rows.map((r) => r.commandZero).sort((a, b) => a - b);
console.log(`${rows.length} trials: forward command zero median ${zero[Math.floor(zero.length / 2)].toFixed(0)} ms, ` +
            `max ${zero[zero.length - 1].toFixed(0)} ms`);
