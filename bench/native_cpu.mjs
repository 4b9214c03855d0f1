// corridord's CPU with native devices against its CPU with the simulator's devices, beyond the simulator (issue 37's
// target: at most the same). Both robots have a base and a laser and no camera, and sit idle, localizing:
//   sim     corridord with the simulator's base and laser: every thread but the simulator's ("sim": physics and ray
//           casting), plus what the simulator's thread spent handing its devices' data to the graph (publishing it,
//           waking the threads that take it: GET /api/v1/devices' handoff_cpu_s), which is the devices' work, not the
//           simulation's;
//   native  corridord with a Create 2 and an RPLIDAR on pseudo-terminals, served by corridor-emulate (the simulator
//           in another process): the drivers' threads, the control loop's pumps (reading, decoding, handing on) and
//           the reconnect watch are all in corridord, measured whole.
// This machine's CPU time per wake-up swings by 2x from minute to minute (a virtual machine: most of a wake-up is the
// hypervisor's), and a robot idling is a few hundred wake-ups a second: the run is cut into 5 s windows, each robot's
// share taken over the same window, and the median of the windows' ratios is the result (with its quartiles).
// --pin puts both daemons on core 0 and the emulator on core 1: the devices are outside a real robot's board, and
// with the emulator on the daemons' core each read of a port follows a switch from another process (the quartiles
// narrow from about 0.8-1.4 to 1.16-1.24).
//   node bench/native_cpu.mjs [seconds=60] [--pin]
import { execFileSync, spawn } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import {
  cpuByName, getJson, nsByName, sleep, sourceDir, startDaemon, threadCpu, waitFor,
} from '../tests/daemon.mjs';

const seconds = Number(process.argv.find((a) => /^\d+$/.test(a)) ?? 60);
const emulate = join(sourceDir, 'build/tools/emulate/corridor-emulate');

// The shipped configuration with `devices` in place of the simulator's slots (and, for native devices, the world's map
// as the robot's map), its relative paths made absolute.
function configWith(devices, mapFile) {
  let config = readFileSync(join(sourceDir, 'config/corridor.yaml'), 'utf8');
  // The devices section, whatever it holds, up to the simulator's that follows it.
  const slots = config.indexOf('\ndevices:\n');
  const after = config.indexOf('\nsim:\n', slots);
  check(slots >= 0 && after > slots, 'the shipped devices section moved');
  config = `${config.slice(0, slots)}\ndevices:\n${devices}\n${config.slice(after)}`;
  if (mapFile) config = config.replace('\nmap:\n  file: ""', `\nmap:\n  file: "${mapFile}"`);
  return config.replaceAll('"worlds/', `"${join(sourceDir, 'config/worlds')}/`);
}

function check(condition, message) {
  if (!condition) throw new Error(message);
}

// What a daemon's threads used between two threadCpu() readings: on-CPU time by thread name, and the user share
// of what is beyond the simulator (in the kernel: system calls, wake-ups, and on a virtual machine the hypervisor's
// part of each; ticks are samples, so a share, not a time).
function used(before, after, span) {
  const byThread = cpuByName(before, after);
  const percent = (ns) => (100 * ns) / 1e9 / span;
  const byName = nsByName(before, after);
  const total = [...byName.values()].reduce((a, b) => a + b, 0);
  const sim = byThread.get('sim') ?? { ns: 0, userTicks: 0, systemTicks: 0 };
  let [user, system] = [0, 0];
  for (const [, t] of byThread) [user, system] = [user + t.userTicks, system + t.systemTicks];
  const userShare = (user - sim.userTicks) / Math.max(1, user + system - sim.userTicks - sim.systemTicks);
  return { total: percent(total), beyondSim: percent(total - sim.ns), byName, percent, userShare };
}

// Both robots run at once and are measured over the same windows, so that what else this machine does in a minute
// (it is shared) falls on both alike.
const simDaemon = await startDaemon({ config: configWith('  camera:\n    driver: none\n') });
const dir = mkdtempSync(join(tmpdir(), 'corridor-native-cpu-'));
// The same laser as the simulator's (its 8 m range: corridor-emulate serves that laser as an RPLIDAR).
const devices = `  base: {driver: create2, port: ${join(dir, 'create2')}}\n`
  + `  laser: {driver: rplidar, port: ${join(dir, 'rplidar')}, max_range_m: 8}\n  camera: {driver: none}\n`;
const config = configWith(devices, join(sourceDir, 'config/worlds/willow_garage/willow-full-0.05.yaml'));
writeFileSync(join(dir, 'emulated.yaml'), configWith('  camera:\n    driver: none\n'));
const emulator = spawn(emulate,
  ['--config', join(dir, 'emulated.yaml'), '--create2', join(dir, 'create2'), '--rplidar', join(dir, 'rplidar')],
  { stdio: 'ignore' });
process.on('exit', () => emulator.kill('SIGTERM'));  // also when the bench fails: a stray emulator loads the machine
await waitFor(() => existsSync(join(dir, 'create2')) && existsSync(join(dir, 'rplidar')), (linked) => linked, 10000,
  'corridor-emulate to link its ports');
const nativeDaemon = await startDaemon({ config });
if (process.argv.includes('--pin')) {
  const pin = (core, pid) => execFileSync('taskset', ['--all-tasks', '--pid', '--cpu-list', core, String(pid)]);
  pin('1', emulator.pid);
  pin('0', simDaemon.pid);
  pin('0', nativeDaemon.pid);
}
await sleep(5000);  // start-up, the first scans and localization settling are not idle
// The CPU seconds a daemon has spent handing its devices' data to the graph.
async function handoffS(daemon) {
  const { status, body } = await getJson(`${daemon.url}/api/v1/devices`);
  check(status === 200, `GET /api/v1/devices: ${status}`);
  return body.devices.reduce((sum, d) => sum + d.handoff_cpu_s, 0);
}
const sample = async () => ({
  cpu: [threadCpu(simDaemon.pid), threadCpu(nativeDaemon.pid)],
  handoff: [await handoffS(simDaemon), await handoffS(nativeDaemon)],
});
// The simulator's devices between two samples: beyond the simulator, and with the simulator's handing on.
const simSide = (a, b, span) => {
  const run = used(a.cpu[0], b.cpu[0], span);
  const handoff = (100 * (b.handoff[0] - a.handoff[0])) / span;
  return { run, handoff, devices: run.beyondSim + handoff };
};
const windows = Math.max(3, Math.round(seconds / 5));
const ratios = [];
const first = await sample();
let last = first;
for (let w = 0; w < windows; ++w) {
  await sleep((seconds * 1000) / windows);
  const now = await sample();
  const span = seconds / windows;
  ratios.push(used(last.cpu[1], now.cpu[1], span).total / simSide(last, now, span).devices);
  last = now;
}
const simDevices = simSide(first, last, seconds);
const sim = simDevices.run;
const native = used(first.cpu[1], last.cpu[1], seconds);
const nativeHandoff = (100 * (last.handoff[1] - first.handoff[1])) / seconds;
await Promise.all([simDaemon.stop(), nativeDaemon.stop()]);
emulator.kill('SIGTERM');
rmSync(dir, { recursive: true, force: true });

console.log(`corridord idle for ${seconds} s, a base and a laser, no camera (time on a CPU, schedstat):`);
const threads = (run) => {
  for (const [name, ns] of [...run.byName].sort((a, b) => b[1] - a[1]).slice(0, 6)) {
    console.log(`    ${name.padEnd(16)} ${run.percent(ns).toFixed(2).padStart(5)} %`);
  }
};
const user = (run) => `${Math.round(100 * run.userShare)} % of it in corridord's own code`;
console.log(`  simulator's devices                        ${simDevices.devices.toFixed(2).padStart(5)} % of one core:`
  + ` ${sim.beyondSim.toFixed(2)} % beyond the simulator's thread, ${simDevices.handoff.toFixed(2)} % its handing`
  + ` their data on (the simulation ${(sim.total - sim.beyondSim - simDevices.handoff).toFixed(2)} %), ${user(sim)}`);
threads(sim);
console.log(`  native devices (Create 2, RPLIDAR)         ${native.total.toFixed(2).padStart(5)} % of one core`
  + ` (${nativeHandoff.toFixed(2)} % handing their data on), ${user(native)}`);
threads(native);
const sorted = [...ratios].sort((a, b) => a - b);
const quantile = (q) => sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))];
console.log(`  ratio native / simulator's devices, median of ${windows} windows of ${Math.round(seconds / windows)} s:`
  + ` ${quantile(0.5).toFixed(2)} (quartiles ${quantile(0.25).toFixed(2)}-${quantile(0.75).toFixed(2)},`
  + ` range ${sorted[0].toFixed(2)}-${sorted.at(-1).toFixed(2)}); over the whole run`
  + ` ${(native.total / simDevices.devices).toFixed(2)}, against beyond the simulator's thread alone`
  + ` ${(native.total / sim.beyondSim).toFixed(2)}`);
