// Localization and mapping on the Radish CARMEN logs (tools/slam_eval), the rows docs/benchmarks.md reports: SLAM on
// each log and seed (relative pose error, local and revisit, with the dead-reckoned odometry's beside it; speed against
// the log's own duration; how noisy the corrected poses are themselves, tools/slam_eval/heading_noise.h), then
// localization in the reference map from the first pose and from nothing.
//   node bench/slam.mjs [--logs DIR] [--seeds 1,2] [--only intel,freiburg-079]
// One process at a time: the speed is that of one core. Needs ./dev build.
import { execFileSync } from 'node:child_process';
import { existsSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const tool = join(root, 'build/tools/slam_eval/corridor-slam-eval');

function option(name, fallback) {
  const i = process.argv.indexOf(name);
  return i > 0 && i + 1 < process.argv.length ? process.argv[i + 1] : fallback;
}
const logs = option('--logs', join(root, '../shared/data/laser_logs'));
const seeds = option('--seeds', '1,2').split(',').map(Number);
const names = option('--only', 'intel,freiburg-079').split(',');
if (!existsSync(tool)) throw new Error(`${tool} is missing: run ./dev build`);

const run = (args) => JSON.parse(execFileSync(tool, [...args, '--json'], { maxBuffer: 1 << 26 }).toString());
const cm = (v) => (100 * v).toFixed(2);
const deg = (v) => v.toFixed(3);

console.log('| log | seed | local cm | local deg | revisit cm | revisit deg | odometry local cm / deg | odometry revisit cm | x real time | loop closures | corrected poses\' own heading noise (deg) |');
console.log('|---|---|---|---|---|---|---|---|---|---|---|');
for (const name of names) {
  const log = join(logs, `${name}-corrected.log.gz`);
  for (const seed of seeds) {
    const r = run([log, '--seed', String(seed), '--reference-noise']);
    const o = r.odometry;
    console.log(`| ${name} | ${seed} | ${cm(r.local.translation_m.mean)} | ${deg(r.local.rotation_deg.mean)} | ` +
      `${cm(r.revisit.translation_m.mean)} | ${deg(r.revisit.rotation_deg.mean)} | ` +
      `${cm(o.local.translation_m.mean)} / ${deg(o.local.rotation_deg.mean)} | ${cm(o.revisit.translation_m.mean)} | ` +
      `${r.speed_x_realtime.toFixed(1)} | ${r.graph.loop_closures} | <= ${r.reference_noise.corrected_poses_deg.toFixed(2)} |`);
  }
}
console.log();
console.log('| log | seed | start | rmse cm | rmse deg | max cm | converged at scan (s) | scans off after | x real time |');
console.log('|---|---|---|---|---|---|---|---|---|');
for (const name of names) {
  const log = join(logs, `${name}-corrected.log.gz`);
  for (const seed of seeds) {
    for (const global of [false, true]) {
      const r = run([log, '--mode', 'localize', '--seed', String(seed), ...(global ? ['--global'] : [])]);
      const e = r.error;
      console.log(`| ${name} | ${seed} | ${global ? 'nothing' : 'first pose'} | ${cm(e.rmse_translation_m)} | ` +
        `${e.rmse_rotation_deg.toFixed(2)} | ${cm(e.max_translation_m)} | ${e.converged_scan} (${e.converged_s?.toFixed(1)}) | ` +
        `${e.scans_off_after_converged} | ${r.speed_x_realtime.toFixed(0)} |`);
    }
  }
}
