// Localization in corridord against the simulator's truth in Willow Garage, issue 20's targets, with the laser or the
// depth camera alone (the simulator's odometry noise as configured):
//   1. missions between random places until the robot has driven --distance metres, sampled at 5 Hz: the error to
//      the truth (RMSE, max), how far from each goal the robot stopped by its own estimate, the localization update's
//      wall time (its latest, sampled: p50, p99), and the daemon's CPU per thread;
//   2. --kidnaps random kidnappings (the robot carried to a random free place and heading): found when the estimate is
//      within 0.2 m and 5 degrees of the truth and not lost, within 15 s; "wrong" when it claims ok elsewhere.
//   node bench/localization.mjs [--sensor laser|depth] [--distance 200] [--kidnaps 20] [--seed 1]
// (--distance 0: the kidnappings alone)
// Needs ./dev build. Run nothing else meanwhile: the times and the CPU are this machine's.
import { execFileSync } from 'node:child_process';

import {
  getJson, nsByName, postJson, readMap, sendJson, sleep, sourceDir, startDaemon, threadCpu,
} from '../tests/daemon.mjs';

function option(name, fallback) {
  const i = process.argv.indexOf(name);
  return i > 0 && i + 1 < process.argv.length ? process.argv[i + 1] : fallback;
}
const sensor = option('--sensor', 'laser');
const distance = Number(option('--distance', '200'));
const kidnaps = Number(option('--kidnaps', '20'));
const seed = Number(option('--seed', '1'));
if (!['laser', 'depth'].includes(sensor)) throw new Error('--sensor is laser or depth');

// mulberry32: a small seeded generator, so that every run visits the same places.
let state32 = seed >>> 0;
const random = () => {
  state32 = (state32 + 0x6d2b79f5) >>> 0;
  let t = state32;
  t = Math.imul(t ^ (t >>> 15), t | 1);
  t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
  return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
};

const mapFile = `${sourceDir}config/worlds/willow_garage/willow-full-0.05.yaml`;
const map = readMap(mapFile);
// A random place with free floor (254) for 0.5 m around, and a random heading.
function freePlace() {
  for (;;) {
    const x = map.origin[0] + random() * map.width * map.resolution;
    const y = map.origin[1] + random() * map.height * map.resolution;
    let free = true;
    for (let dx = -0.5; dx <= 0.5 && free; dx += map.resolution) {
      for (let dy = -0.5; dy <= 0.5 && free; dy += map.resolution) {
        if (dx * dx + dy * dy <= 0.25 && map.cell(x + dx, y + dy) !== 254) free = false;
      }
    }
    if (free) return { x, y, yaw: (random() * 2 - 1) * Math.PI };
  }
}

const wrap = (a) => Math.atan2(Math.sin(a), Math.cos(a));
const errorOf = (s) => [Math.hypot(s.pose.x - s.sim_true_pose.x, s.pose.y - s.sim_true_pose.y),
  Math.abs(wrap(s.pose.yaw - s.sim_true_pose.yaw)) * 180 / Math.PI];
const percentile = (values, p) => {
  const sorted = [...values].sort((a, b) => a - b);
  return sorted[Math.min(sorted.length - 1, Math.floor(p * sorted.length))];
};
const rms = (values) => Math.sqrt(values.reduce((a, v) => a + v * v, 0) / values.length);

const daemon = await startDaemon({ config: `
map: {file: "${mapFile}"}
devices: {laser: {driver: ${sensor === 'laser' ? 'sim' : 'none'}}}
sim:
  world: "${mapFile}"
  start: {x_m: 24.38, y_m: 24.07, yaw_deg: 90}
localization: {source: mcl}
` });
const state = async () => (await getJson(`${daemon.url}/api/v1/state`)).body;
const localization = async () => (await getJson(`${daemon.url}/api/v1/localization`)).body;
const pid = Number(execFileSync('pgrep', ['-n', 'corridord']).toString());

try {
  // 1. Missions.
  await sleep(3000);
  const errors = [];
  const yawErrors = [];
  const updates = [];
  const stops = [];
  let driven = 0;
  let last = (await state()).sim_true_pose;
  let missions = 0;
  let failed = 0;
  const cpuBefore = threadCpu(pid);
  const started = Date.now();
  let lastCount = -1;
  while (driven < distance) {
    let goal = freePlace();
    while (Math.hypot(goal.x - last.x, goal.y - last.y) < 8) goal = freePlace();
    const res = await postJson(`${daemon.url}/api/v1/missions`, { waypoints: [{ x: goal.x, y: goal.y }] });
    if (res.status !== 201) throw new Error(JSON.stringify(res.body));
    ++missions;
    let s;
    const deadline = Date.now() + 240000;
    do {
      await sleep(200);
      s = await state();
      const [m, deg] = errorOf(s);
      errors.push(m);
      yawErrors.push(deg);
      driven += Math.hypot(s.sim_true_pose.x - last.x, s.sim_true_pose.y - last.y);
      last = s.sim_true_pose;
      const node = s.nodes.find((n) => n.name === 'localization');
      const loop = node?.callbacks.find((c) => c.name === (sensor === 'laser' ? 'scan' : 'frame'));
      if (loop && loop.count !== lastCount) {
        updates.push(loop.last_ms);
        lastCount = loop.count;
      }
    } while (s.mission?.status === 'active' && Date.now() < deadline);
    if (s.mission?.status === 'succeeded') {
      stops.push(Math.hypot(s.pose.x - goal.x, s.pose.y - goal.y));
    } else {
      ++failed;
      await postJson(`${daemon.url}/api/v1/missions/${s.mission.id}/cancel`, {});
    }
  }
  const seconds = (Date.now() - started) / 1000;
  const cpu = nsByName(cpuBefore, threadCpu(pid));
  const percent = (ns) => (100 * ns) / 1e9 / seconds;
  const total = [...cpu.values()].reduce((a, b) => a + b, 0);
  if (distance > 0) {
    console.log(`${sensor}: ${missions} missions (${failed} not succeeded), ${driven.toFixed(0)} m in ${seconds.toFixed(0)} s`);
    console.log(`  error to the truth: RMSE ${(100 * rms(errors)).toFixed(1)} cm, ${rms(yawErrors).toFixed(2)} deg; ` +
      `max ${(100 * Math.max(...errors)).toFixed(1)} cm, ${Math.max(...yawErrors).toFixed(2)} deg (${errors.length} samples)`);
    console.log(`  stopped from the goal by its own estimate: max ${(100 * Math.max(...stops)).toFixed(1)} cm ` +
      `(${stops.length} goals)`);
    console.log(`  localization update (sampled latest): p50 ${percentile(updates, 0.5).toFixed(2)} ms, ` +
      `p99 ${percentile(updates, 0.99).toFixed(2)} ms, max ${Math.max(...updates).toFixed(2)} ms (${updates.length} samples)`);
    console.log(`  CPU: total ${percent(total).toFixed(1)} % of one core, beyond the sim ${percent(total - (cpu.get('sim') ?? 0)).toFixed(1)} %, ` +
      [...cpu].sort((a, b) => b[1] - a[1]).map(([n, t]) => `${n} ${percent(t).toFixed(1)}`).join(', '));
  }

  // 2. Kidnappings.
  const times = [];
  let wrong = 0;
  for (let k = 0; k < kidnaps; ++k) {
    const place = freePlace();
    await sendJson('PUT', `${daemon.url}/api/v1/sim/pose`, place);
    const t0 = Date.now();
    let found = false;
    let claimed = false;
    let lostAt = null;
    let last = '';
    while (Date.now() - t0 < 15000) {
      await sleep(200);
      const [s, l] = [await state(), await localization()];
      if (Math.hypot(s.sim_true_pose.x - place.x, s.sim_true_pose.y - place.y) > 0.3) continue;  // not yet carried
      const [m, deg] = errorOf(s);
      if (l.health === 'lost' && lostAt === null) lostAt = (Date.now() - t0) / 1000;
      last = `${l.health}, ${m.toFixed(2)} m ${deg.toFixed(0)} deg off`;
      if (l.health !== 'lost' && m < 0.2 && deg < 5) { found = true; break; }
      claimed = l.health === 'ok' && m > 1.0;
    }
    if (found) times.push((Date.now() - t0) / 1000);
    else wrong += claimed;
    // One line each: where to, whether and when it knew it was lost, how it ended.
    console.log(`    ${k + 1}: to (${place.x.toFixed(1)}, ${place.y.toFixed(1)}, ${(place.yaw * 180 / Math.PI).toFixed(0)} deg): ` +
      `${found ? `found in ${((Date.now() - t0) / 1000).toFixed(1)} s` : 'not found'}; lost ` +
      `${lostAt === null ? 'never' : `after ${lostAt.toFixed(1)} s`}; last ${last}`);
    // Whatever happened, the next one starts localized where the robot is.
    const truth = (await state()).sim_true_pose;
    await sendJson('PUT', `${daemon.url}/api/v1/localization/pose`, { ...truth, sigma_m: 0.05, sigma_yaw: 0.05 });
    await sleep(1500);
  }
  console.log(`  kidnapped ${kidnaps} times: found ${times.length} within 15 s (median ${percentile(times, 0.5)?.toFixed(1)} s, ` +
    `max ${Math.max(...times).toFixed(1)} s); ${wrong} times it claimed ok elsewhere at the end`);
} finally {
  await daemon.stop();
}
