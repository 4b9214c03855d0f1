// Starts a real corridord for tests: its own free port, its own state directory, the simulator.
// The packages tests use (ws, ajv, playwright-core) are installed with the console in web/.
import { execFileSync, spawn, spawnSync } from 'node:child_process';
import { mkdtempSync, readdirSync, rmSync, writeFileSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { Worker } from 'node:worker_threads';

export const sourceDir = new URL('..', import.meta.url).pathname;
export const require = createRequire(join(sourceDir, 'web/package.json'));
export const corridord = process.env.CORRIDORD ?? join(sourceDir, 'build/server/corridord');

// Runs corridord to completion (for --help, bad configs); resolves {code, stdout, stderr}.
export function runCorridord(args, timeoutMs = 20000) {
  return new Promise((resolve, reject) => {
    const proc = spawn(corridord, args, { stdio: ['ignore', 'pipe', 'pipe'] });
    let stdout = '';
    let stderr = '';
    proc.stdout.on('data', (d) => { stdout += d; });
    proc.stderr.on('data', (d) => { stderr += d; });
    const timer = setTimeout(() => { proc.kill('SIGKILL'); reject(new Error(`corridord ${args} timed out`)); }, timeoutMs);
    proc.on('exit', (code) => { clearTimeout(timer); resolve({ code, stdout, stderr }); });
  });
}

// The credentials of the daemons this process started, by origin: an admin API token (minted offline with
// `corridord token create` before the daemon starts) that the helpers below send, and a console user for browsers.
const credentials = new Map();
export const consoleUser = { username: 'tester', password: 'corridor-tests' };

// The Authorization header for the daemon at `url` ({} for a daemon this process did not start).
export function authHeaders(url) {
  const token = credentials.get(new URL(url).origin);
  return token ? { Authorization: `Bearer ${token}` } : {};
}

// fetch() with the test's admin token.
export function apiFetch(url, init = {}) {
  return fetch(url, { ...init, headers: { ...authHeaders(url), ...(init.headers ?? {}) } });
}

// An API token minted offline into `stateDir`: what root on the robot does with `corridord token create`.
export function mintToken(stateDir, role = 'admin', name = 'tests') {
  const out = spawnSync(corridord, ['token', 'create', '--role', role, '--name', name, '--state-dir', stateDir],
    { encoding: 'utf8' });
  if (out.status !== 0) throw new Error(`corridord token create: ${out.stderr}`);
  return out.stdout.trim();
}

// Starts corridord; `config` (YAML text) replaces the shipped config when given; `stateDir` keeps the state of an
// earlier daemon (it is then left in place at stop). Resolves once it listens.
export async function startDaemon({ config = null, args = [], stateDir: keptStateDir = null } = {}) {
  const stateDir = keptStateDir ?? mkdtempSync(join(tmpdir(), 'corridor-test-'));
  const configArgs = [];
  if (config !== null) {
    const file = join(stateDir, 'corridor.yaml');
    writeFileSync(file, config);
    configArgs.push('--config', file);
  } else {
    configArgs.push('--config', join(sourceDir, 'config/corridor.yaml'));
  }
  const token = mintToken(stateDir);
  const proc = spawn(corridord, [...configArgs, '--port', '0', '--state-dir', stateDir, ...args],
    { stdio: ['ignore', 'ignore', 'pipe'] });
  let log = '';
  const [scheme, port] = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`corridord did not start:\n${log}`)), 30000);
    proc.stderr.on('data', (d) => {
      log += d;
      const m = /listening on (https?):\/\/[^:]+:(\d+)/.exec(log);
      if (m) { clearTimeout(timer); resolve([m[1], Number(m[2])]); }
    });
    proc.on('exit', (code) => { clearTimeout(timer); reject(new Error(`corridord exited with ${code}:\n${log}`)); });
  });
  const exited = new Promise((resolve) => proc.on('exit', (code, signal) => resolve({ code, signal })));
  credentials.set(`${scheme}://127.0.0.1:${port}`, token);
  return {
    port,
    pid: proc.pid,
    url: `${scheme}://127.0.0.1:${port}`,
    stateDir,
    log: () => log,
    exited,
    kill: (signal) => proc.kill(signal),  // without the graceful stop (a crash, a power cut)
    async stop() {
      proc.kill('SIGTERM');
      const result = await exited;
      if (!keptStateDir) rmSync(stateDir, { recursive: true, force: true });
      return result;
    },
  };
}

// A self-signed certificate for 127.0.0.1 in `dir`, made by the openssl command line.
export function makeCertificate(dir, name) {
  const key = join(dir, `${name}.key`);
  const cert = join(dir, `${name}.pem`);
  execFileSync('openssl', ['req', '-x509', '-newkey', 'rsa:2048', '-nodes', '-days', '1', '-subj', '/CN=127.0.0.1',
    '-addext', 'subjectAltName=IP:127.0.0.1', '-keyout', key, '-out', cert], { stdio: 'ignore' });
  return { key: readFileSync(key), cert: readFileSync(cert), certFile: cert, keyFile: key };
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// A request with the test's admin token unless `headers` says otherwise ({} sends no credentials).
export async function sendJson(method, url, body, contentType = 'application/json', headers = authHeaders(url)) {
  const res = await fetch(url, {
    method, headers: body === undefined ? headers : { ...headers, 'Content-Type': contentType },
    body: body === undefined || typeof body === 'string' ? body : JSON.stringify(body),
  });
  const text = await res.text();
  return { status: res.status, type: res.headers.get('content-type'), body: text ? JSON.parse(text) : null };
}

export const postJson = (url, body, contentType) => sendJson('POST', url, body, contentType);
export const getJson = (url) => sendJson('GET', url);

// Polls until `predicate(value)` holds for `get()`'s value; returns that value, or throws after `ms`.
export async function waitFor(get, predicate, ms, what) {
  const end = Date.now() + ms;
  let value;
  while (Date.now() < end) {
    value = await get();
    if (predicate(value)) return value;
    await sleep(100);
  }
  throw new Error(`timed out waiting for ${what}; last: ${JSON.stringify(value)?.slice(0, 400)}`);
}

// Debian's chromium driven by playwright-core, headless, with the flags this machine's closed network needs.
export function launchBrowser(extraArgs = []) {
  const { chromium } = require('playwright-core');
  return chromium.launch({
    executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
    // WebGL (the console's 3D map) from the software renderer: there is no GPU here.
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update',
      '--disable-sync', ...extraArgs],
  });
}

// Logs `page` in to the console of the daemon at `url` through its login form as `user`, by default the test's
// console user (an admin, created with the test's token the first time), and waits until the console is connected.
export async function gotoConsole(page, url, user = null) {
  if (user === null) {
    const made = await postJson(`${url}/api/v1/users`, { ...consoleUser, role: 'admin' });
    if (made.status !== 201 && made.status !== 409) throw new Error(`console user: ${JSON.stringify(made.body)}`);
  }
  user ??= consoleUser;
  await page.goto(url);
  await page.getByTestId('login-username').fill(user.username);
  await page.getByTestId('login-password').fill(user.password);
  await page.getByTestId('login-submit').click();
  await page.getByTestId('connection').filter({ hasText: 'connected' }).waitFor({ timeout: 15000 });
}

// Opens the console of the daemon at `url` in a new page of `browser`, logged in, and waits until it is connected;
// `errors` collects the page's uncaught errors.
export async function openConsole(browser, url, viewport = { width: 1280, height: 800 }) {
  const page = await browser.newPage({ viewport });
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  await gotoConsole(page, url);
  return { page, errors };
}

// A validator for a schema of the OpenAPI document (JSON Schema 2020-12, as OpenAPI 3.1 uses).
export function openApiValidator() {
  const Ajv2020 = require('ajv/dist/2020').default;
  const doc = JSON.parse(readFileSync(join(sourceDir, 'server/api/openapi.json'), 'utf8'));
  const ajv = new Ajv2020({ strict: false, allErrors: true });
  ajv.addSchema({ $id: 'openapi', components: doc.components });
  return {
    doc,
    check(name, value) {
      const validate = ajv.getSchema(`openapi#/components/schemas/${name}`);
      if (!validate(value)) throw new Error(`${name}: ${ajv.errorsText(validate.errors)}\n${JSON.stringify(value)}`);
    },
  };
}

// Sends teleop over REST every 100 ms, as a joystick would, until the robot's state satisfies `predicate`; returns
// that state, or throws after `ms`.
export function driveUntil(url, command, predicate, ms, what) {
  return waitFor(async () => {
    await postJson(`${url}/api/v1/teleop`, command);
    return (await getJson(`${url}/api/v1/state`)).body;
  }, predicate, ms, `driving until ${what}`);
}

// Centres the console's map in `page` on `latLng` at `zoom` and waits until the page has drawn it.
export function showMap(page, latLng, zoom) {
  return page.evaluate(([at, z]) => new Promise((drawn) => {
    window.corridorConsole.view.map.setView(at, z, { animate: false });
    requestAnimationFrame(() => requestAnimationFrame(drawn));
  }), [latLng, zoom]);
}

// An empty room `width` x `height` metres at 5 cm, walled by one cell; its inside corner at (0, 0).
export function writeRoom(dir, width, height) {
  const w = Math.round(width / 0.05) + 2;
  const h = Math.round(height / 0.05) + 2;
  const header = Buffer.from(`P5\n${w} ${h}\n255\n`);
  const pixels = Buffer.alloc(w * h, 254);
  for (let x = 0; x < w; ++x) { pixels[x] = 0; pixels[(h - 1) * w + x] = 0; }
  for (let y = 0; y < h; ++y) { pixels[y * w] = 0; pixels[y * w + w - 1] = 0; }
  writeFileSync(join(dir, 'room.pgm'), Buffer.concat([header, pixels]));
  writeFileSync(join(dir, 'room.yaml'),
    'image: room.pgm\nresolution: 0.05\norigin: [-0.05, -0.05, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n');
  return join(dir, 'room.yaml');
}

// The benchmarks' mission room: the `sim:` section of a 12 x 8 m room (written to `dir`) with two pillars the map does
// not show and three people walking, the robot at its west end facing east; more `sim:` keys may follow it.
export function pillarRoom(dir) {
  return `sim:
  world: "${writeRoom(dir, 12, 8)}"
  start: {x_m: 1.0, y_m: 4.0, yaw_deg: 0}
  obstacles:
    - {shape: cylinder, x_m: 4.0, y_m: 4.1, size_m: 0.3, height_m: 1.0}
    - {shape: box, x_m: 8.0, y_m: 3.8, size_m: 0.3, height_m: 1.0}
  pedestrians: 3
`;
}

// A map_server map (its YAML and 8-bit P5 PGM): resolution, origin, size, and the grey of each pixel, row 0 at the
// top. cell(x, y) is the grey at a point of the map frame (undefined off the map).
export function readMap(yamlFile) {
  const yaml = readFileSync(yamlFile, 'utf8');
  const resolution = Number(/resolution:\s*([\d.]+)/.exec(yaml)[1]);
  const origin = /origin:\s*\[\s*([-\d.]+),\s*([-\d.]+)/.exec(yaml).slice(1, 3).map(Number);
  const pgm = readFileSync(join(yamlFile, '..', /image:\s*(\S+)/.exec(yaml)[1]));
  // The header: magic, width, height, maximum, each after whitespace and comments.
  const fields = [];
  let i = 0;
  const space = (b) => b === 0x20 || b === 0x0a || b === 0x0d || b === 0x09;
  while (fields.length < 4) {
    while (space(pgm[i])) ++i;
    if (pgm[i] === 0x23) { while (pgm[i] !== 0x0a) ++i; continue; }
    let field = '';
    while (!space(pgm[i])) field += String.fromCharCode(pgm[i++]);
    fields.push(field);
  }
  const [width, height] = [Number(fields[1]), Number(fields[2])];
  const grey = pgm.subarray(i + 1);
  const cell = (x, y) => {
    const col = Math.floor((x - origin[0]) / resolution);
    const row = height - 1 - Math.floor((y - origin[1]) / resolution);
    return col >= 0 && col < width && row >= 0 && row < height ? grey[row * width + col] : undefined;
  };
  return { resolution, origin, width, height, grey, cell };
}

// Each thread of process `pid`, with its name (corridord names its executor threads: control, mapping, planning,
// perception, io, sim, and the native drivers' dev-*): its time on a CPU in nanoseconds, as the scheduler counts it
// (schedstat: exact, where utime and stime are sampled at the 100 Hz tick, a few samples a second for a thread at
// 1 % of a core), and those two in ticks, for the split between the thread's own code and the kernel's work for it.
export function threadCpu(pid) {
  const out = new Map();
  for (const tid of readdirSync(`/proc/${pid}/task`)) {
    const task = `/proc/${pid}/task/${tid}`;
    const stat = readFileSync(`${task}/stat`, 'utf8');
    const name = stat.slice(stat.indexOf('(') + 1, stat.lastIndexOf(')'));
    const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
    const ns = Number(readFileSync(`${task}/schedstat`, 'utf8').split(' ')[0]);
    out.set(tid, { name, ns, userTicks: Number(fields[11]), systemTicks: Number(fields[12]) });
  }
  return out;
}

// Nanoseconds on a CPU by thread name between two threadCpu() readings.
export function nsByName(before, after) {
  return new Map([...cpuByName(before, after)].map(([name, { ns }]) => [name, ns]));
}

// What each thread name used between two threadCpu() readings (threads of one name summed): nanoseconds on a CPU,
// and user and system ticks.
export function cpuByName(before, after) {
  const byName = new Map();
  for (const [tid, now] of after) {
    const then = before.get(tid) ?? { ns: 0, userTicks: 0, systemTicks: 0 };
    const sum = byName.get(now.name) ?? { ns: 0, userTicks: 0, systemTicks: 0 };
    sum.ns += now.ns - then.ns;
    sum.userTicks += now.userTicks - then.userTicks;
    sum.systemTicks += now.systemTicks - then.systemTicks;
    byName.set(now.name, sum);
  }
  return byName;
}

// Keeps `threads` cores busy (worker threads spinning) until the returned function is called: a machine loaded by
// other work, for checks whose outcome must not depend on the load.
export function loadMachine(threads = 2) {
  const workers = Array.from({ length: threads },
    () => new Worker('for (;;) {}', { eval: true }));
  return async () => { await Promise.all(workers.map((w) => w.terminate())); };
}
