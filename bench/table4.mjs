// DPoom's Tables 3 and 4 (and ASNS's scenario tables) through the daemon's graph: every setting docs/benchmarks.md
// reports, each seed one run of tools/scenario (10 worlds x 3 runs unless the setting says), then one Markdown row
// per setting (success per seed and over all seeds, collisions, those the robot drove into, timeouts, mean time to
// goal, milliseconds per depth frame).
//   node bench/table4.mjs [--jobs N] [--only NAME[,NAME...]] [--seeds A-B|A,B,...] [--out DIR] [--reuse]
// --jobs: scenario processes at once (default 1: the per-frame times are then measured on an otherwise idle core).
// --only: settings by name (see SETTINGS); default all. --out: where each run's JSON goes (default build/table4).
// --reuse: a seed whose JSON is already in --out is read, not run again (to finish or merge long evaluations; the
// JSON must come from the same build).
// Needs ./dev build (build/tools/scenario/corridor-scenario).
import { execFile } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const scenario = join(root, 'build/tools/scenario/corridor-scenario');

// name, flags, seeds. The paper's crowd (5 people placed in the robot's way, walked once, then standing) is the
// protocol of Table 4; the pacing crowd is our harder one. MORP-IL and Takiguchi's policy drive with the shipped
// networks, on seeds their training never used (config/policies/README.md).
const il = ['--policy', 'morp-il', '--weights', join(root, 'config/policies/morp_il.weights')];
const tk = ['--policy', 'takiguchi', '--takiguchi-weights', join(root, 'config/policies/takiguchi.weights')];
// With the laser, Takiguchi's network sees all round: its own network, 180 rays over 360 degrees.
const tkLaser = ['--policy', 'takiguchi', '--takiguchi-weights', join(root, 'config/policies/takiguchi_laser.weights'),
                 '--takiguchi-rays', '180', '--takiguchi-field', '360', '--laser'];
const SETTINGS = [
  ['paper', ['--policy', 'morp-rb'], [1, 2, 3, 4, 5]],
  ['paper-static', ['--policy', 'morp-rb', '--static', '9'], [1, 2]],
  ['paper-laser', ['--policy', 'morp-rb', '--laser'], [1, 2]],
  ['paper-no-tracking', ['--policy', 'morp-rb', '--no-camera-tracking'], [1, 2]],
  ['paper-voxel', ['--policy', 'voxel-reactive'], [1, 2]],
  ['paper-static-voxel', ['--policy', 'voxel-reactive', '--static', '9'], [1, 2]],
  ['pacing', ['--policy', 'morp-rb', '--crowd', 'pacing'], [1, 2]],
  ['pacing-laser', ['--policy', 'morp-rb', '--crowd', 'pacing', '--laser'], [1, 2]],
  ['paper-il', il, [1, 2]],
  ['paper-static-il', [...il, '--static', '9'], [1, 2]],
  ['pacing-il', [...il, '--crowd', 'pacing'], [1, 2]],
  ['paper-takiguchi', tk, [1, 2]],
  ['paper-static-takiguchi', [...tk, '--static', '9'], [1, 2]],
  ['pacing-takiguchi', [...tk, '--crowd', 'pacing'], [1, 2]],
  ['pacing-laser-il', [...il, '--crowd', 'pacing', '--laser'], [1, 2]],
  ['pacing-laser-takiguchi', [...tkLaser, '--crowd', 'pacing'], [1, 2]],
  // People who see the robot and keep clear of it (the others walk as if it were not there).
  ['pacing-seeing', ['--policy', 'morp-rb', '--crowd', 'pacing', '--people-see-robot'], [1, 2]],
  ['pacing-seeing-il', [...il, '--crowd', 'pacing', '--people-see-robot'], [1, 2]],
  ['pacing-seeing-takiguchi', [...tk, '--crowd', 'pacing', '--people-see-robot'], [1, 2]],
  // ASNS's scenario tables (issue 41): its three settings with low, medium and large obstacles, FLMC against MORP-RB,
  // the depth sensor, the stereo pair and ASNS's camera (MMSVF), each also on the pan servo with the gaze (-pan);
  // no people, 3 obstacles, 20 runs a seed (asns-corridor-low-flmc-depth, asns-room-medium-morp-rb-mmsvf-pan, ...).
  ...['corridor', 'room', 'open'].flatMap((setting) => ['low', 'medium', 'large'].flatMap((size) =>
    ['flmc', 'morp-rb'].flatMap((policy) => ['depth', 'stereo', 'mmsvf'].flatMap((camera) => ['', '-pan'].map((pan) => [
      `asns-${setting}-${size}-${policy}-${camera}${pan}`,
      ['--policy', policy, '--setting', setting, '--obstacle-size', size, '--static', '3', '--pedestrians', '0',
       '--camera', camera, ...(pan ? ['--pan'] : []), '--worlds', '10', '--runs', '2'],
      [1]]))))),
];

function option(name, fallback) {
  const i = process.argv.indexOf(name);
  return i >= 0 ? process.argv[i + 1] : fallback;
}
const jobs = Number(option('--jobs', '1'));
const only = option('--only', null)?.split(',');
const out = option('--out', join(root, 'build/table4'));
const reuse = process.argv.includes('--reuse');
// --seeds A-B or A,B,...: every chosen setting on these seeds instead of its own (30 runs a seed: 1-10 makes 300).
const seedList = option('--seeds', null);
function parseSeeds(text) {
  const range = /^(\d+)-(\d+)$/.exec(text);
  const seeds = range ? Array.from({ length: Number(range[2]) - Number(range[1]) + 1 }, (_, i) => Number(range[1]) + i)
                      : text.split(',').map(Number);
  if (!seeds.length || seeds.some((n) => !Number.isInteger(n) || n < 0)) {
    throw new Error(`--seeds: expected A-B or A,B,..., got '${text}'`);
  }
  return seeds;
}
const seedOverride = seedList ? parseSeeds(seedList) : null;
if (!Number.isInteger(jobs) || jobs < 1) throw new Error('--jobs: expected a positive integer');
if (!existsSync(scenario)) throw new Error(`${scenario} is not built: ./dev build`);
const settings = SETTINGS.filter(([name]) => !only || only.includes(name))
  .map(([name, flags, seeds]) => [name, flags, seedOverride ?? seeds]);
if (only && settings.length !== only.length) throw new Error(`--only: known settings are ${SETTINGS.map((s) => s[0])}`);
mkdirSync(out, { recursive: true });

const queue = settings.flatMap(([name, flags, seeds]) => seeds.map((seed) => ({ name, flags, seed })));
const results = new Map();  // "name seed" -> the scenario's JSON
async function worker() {
  for (let job = queue.shift(); job; job = queue.shift()) {
    const file = join(out, `${job.name}-seed${job.seed}.json`);
    if (reuse && existsSync(file)) {
      results.set(`${job.name} ${job.seed}`, JSON.parse(readFileSync(file, 'utf8')));
      continue;
    }
    const args = ['--pedestrians', '5', ...job.flags, '--seed', String(job.seed), '--json', '--quiet'];
    const json = await new Promise((resolve, reject) => {
      execFile(scenario, args, { maxBuffer: 1 << 26 }, (error, stdout, stderr) => {
        if (error) reject(new Error(`${job.name} seed ${job.seed}: ${stderr || error.message}`));
        else resolve(JSON.parse(stdout));
      });
    });
    writeFileSync(file, JSON.stringify(json, null, 1));
    results.set(`${job.name} ${job.seed}`, json);
    const s = json.summary[0];
    console.error(`${job.name} seed ${job.seed}: success ${s.success.toFixed(2)}, collision ${s.collision.toFixed(2)}`);
  }
}
await Promise.all(Array.from({ length: jobs }, worker));

const f = (x, digits = 2) => x.toFixed(digits);
// A collision with a person, by when that person was last in the camera's view (the simulator's truth): never since
// the start, more than a second before, or within the last second.
console.log('| setting | seeds | success per seed | success | collision | robot-caused | ' +
            'person last in view never / > 1 s / <= 1 s before | timeout | time to goal | ' +
            'path | closest person | depth ms | policy ms | total ms | p99 ms |');
console.log('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|');
for (const [name, , seeds] of settings) {
  const runs = seeds.flatMap((seed) => results.get(`${name} ${seed}`).runs);
  const summaries = seeds.map((seed) => results.get(`${name} ${seed}`).summary[0]);
  const count = (pred) => runs.filter(pred).length;
  const successes = runs.filter((r) => r.outcome === 'success');
  const time = successes.reduce((a, r) => a + r.time_s, 0) / Math.max(successes.length, 1);
  const path = successes.reduce((a, r) => a + r.path_length_m, 0) / Math.max(successes.length, 1);
  // The closest a person came: the mean over runs of each run's closest gap (footprint to footprint), and the least.
  const gaps = runs.map((r) => r.closest_person_m).filter((g) => g !== null && g !== undefined);
  // (A collision's gap is 0 or a little under: shown as 0.)
  const least = Math.max(0, Math.min(...gaps));
  const people = runs.filter((r) => r.outcome === 'collision' && r.collided_with === 'person');
  const inView = people.every((r) => 'person_in_view_s' in r)
    ? [(s) => s === null, (s) => s !== null && s > 1, (s) => s !== null && s <= 1]
        .map((when) => f(people.filter((r) => when(r.person_in_view_s)).length / runs.length, 3)).join(' / ')
    : '-';  // runs from before the field
  const closest = gaps.length ? `${f(gaps.reduce((a, g) => a + g, 0) / gaps.length)} (least ${f(least)}) m` : '-';
  // Per-frame times: means weighted by frames; the p99 is the worst seed's.
  const frames = summaries.reduce((a, s) => a + s.frames, 0);
  const mean = (key) => summaries.reduce((a, s) => a + s[key] * s.frames, 0) / Math.max(frames, 1);
  console.log(`| ${name} | ${seeds.join(', ')} | ${summaries.map((s) => f(s.success)).join(' / ')} | ` +
              `${f(successes.length / runs.length, 3)} (${successes.length} of ${runs.length}) | ` +
              `${f(count((r) => r.outcome === 'collision') / runs.length, 3)} | ` +
              `${f(count((r) => r.outcome === 'collision' && r.robot_drove_into_it) / runs.length, 3)} | ` +
              `${inView} | ` +
              `${f(count((r) => r.outcome === 'timeout' || r.outcome === 'no_path') / runs.length, 3)} | ` +
              `${successes.length ? f(time, 1) + ' s' : '-'} | ${successes.length ? f(path, 1) + ' m' : '-'} | ` +
              `${closest} | ${f(mean('depth_ms'), 3)} | ${f(mean('policy_ms'), 3)} | ` +
              `${f(mean('total_ms'), 3)} | ${f(Math.max(...summaries.map((s) => s.total_p99_ms)), 2)} |`);
}
// Which runs failed, to look into with corridor-scenario --only W/R --trace.
for (const [name, , seeds] of settings) {
  for (const seed of seeds) {
    for (const r of results.get(`${name} ${seed}`).runs.filter((r) => r.outcome !== 'success')) {
      const caused = r.robot_drove_into_it ? ', robot-caused' : '';
      const seen = !('person_in_view_s' in r) ? ''
        : r.person_in_view_s === null ? ', never in view' : `, in view ${f(r.person_in_view_s, 1)} s before`;
      const what = r.collided_with ? ` with ${r.collided_with}${caused}${seen}` : '';
      console.log(`${name} seed ${seed} world ${r.world} run ${r.run}: ${r.outcome}${what} at ${f(r.time_s, 1)} s`);
    }
  }
}
