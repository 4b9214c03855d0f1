// corridord's CPU with native devices against its CPU with the simulator's devices, beyond the simulator (issue 37's
// target: at most the same). Both robots have a base and a laser and no camera, and sit idle, localizing:
//   sim     corridord with the simulator's base and laser (its "sim" thread, physics and ray casting, left out);
//   native  corridord with a Create 2 and an RPLIDAR on pseudo-terminals, served by corridor-emulate (the simulator
//           in another process): the drivers' threads, their decoding and their reconnect watch are all in corridord.
//   node bench/native_cpu.mjs [seconds=30]
import { execFileSync, spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import { sleep, sourceDir, startDaemon, threadTicks } from '../tests/daemon.mjs';

const seconds = Number(process.argv.find((a) => /^\d+$/.test(a)) ?? 30);
const emulate = join(sourceDir, 'build/tools/emulate/corridor-emulate');
const ticksPerSecond = Number(execFileSync('getconf', ['CLK_TCK']).toString());

// The shipped configuration with `devices` in place of the simulator's slots (and, for native devices, the world's map
// as the robot's map), its relative paths made absolute.
function configWith(devices, mapFile) {
  let config = readFileSync(join(sourceDir, 'config/corridor.yaml'), 'utf8');
  const slots = '\ndevices:\n  base:\n    driver: sim\n  laser:\n    driver: sim\n  camera:\n    driver: sim\n';
  check(config.includes(slots), 'the shipped devices block moved');
  config = config.replace(slots, `\ndevices:\n${devices}`);
  if (mapFile) config = config.replace('\nmap:\n  file: ""', `\nmap:\n  file: "${mapFile}"`);
  return config.replaceAll('"worlds/', `"${join(sourceDir, 'config/worlds')}/`);
}

function check(condition, message) {
  if (!condition) throw new Error(message);
}

async function measure(daemon) {
  const pid = Number(execFileSync('pgrep', ['-n', 'corridord']).toString());
  await sleep(5000);  // start-up, the first scans and localization settling are not idle
  const before = threadTicks(pid);
  await sleep(seconds * 1000);
  const after = threadTicks(pid);
  const byName = new Map();
  for (const [tid, { name, ticks }] of after) {
    byName.set(name, (byName.get(name) ?? 0) + ticks - (before.get(tid)?.ticks ?? 0));
  }
  const total = [...byName.values()].reduce((a, b) => a + b, 0);
  const percent = (ticks) => (100 * ticks) / ticksPerSecond / seconds;
  return { total: percent(total), beyondSim: percent(total - (byName.get('sim') ?? 0)), byName, percent };
}

const simDaemon = await startDaemon({ config: configWith('  camera:\n    driver: none\n') });
const sim = await measure(simDaemon);
await simDaemon.stop();

const dir = mkdtempSync(join(tmpdir(), 'corridor-native-cpu-'));
const devices = `  base: {driver: create2, port: ${join(dir, 'create2')}}\n`
  + `  laser: {driver: rplidar, port: ${join(dir, 'rplidar')}}\n  camera: {driver: none}\n`;
const config = configWith(devices, join(sourceDir, 'config/worlds/willow_garage/willow-full-0.05.yaml'));
writeFileSync(join(dir, 'emulated.yaml'), configWith('  camera:\n    driver: none\n'));
const emulator = spawn(emulate,
  ['--config', join(dir, 'emulated.yaml'), '--create2', join(dir, 'create2'), '--rplidar', join(dir, 'rplidar')],
  { stdio: 'ignore' });
await sleep(1000);  // its pseudo-terminals linked
const nativeDaemon = await startDaemon({ config });
const native = await measure(nativeDaemon);
await nativeDaemon.stop();
emulator.kill('SIGTERM');
rmSync(dir, { recursive: true, force: true });

console.log(`corridord idle for ${seconds} s, a base and a laser, no camera:`);
console.log(`  simulator's devices, beyond the simulator  ${sim.beyondSim.toFixed(1).padStart(5)} % of one core`
  + ` (the simulator ${(sim.total - sim.beyondSim).toFixed(1)} %)`);
const threads = (run) => {
  for (const [name, ticks] of [...run.byName].sort((a, b) => b[1] - a[1]).slice(0, 6)) {
    console.log(`    ${name.padEnd(16)} ${run.percent(ticks).toFixed(1).padStart(5)} %`);
  }
};
threads(sim);
console.log(`  native devices (Create 2, RPLIDAR)         ${native.total.toFixed(1).padStart(5)} % of one core`);
threads(native);
console.log(`  ratio native / sim beyond the simulator    ${(native.total / sim.beyondSim).toFixed(2)}`);
