// The console in a real browser (Debian's chromium through playwright-core) against a real corridord:
// open it, see the map and the live robot, drive with the keyboard, watch the pose change, take a screenshot.
import assert from 'node:assert/strict';
import { mkdirSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import {
  gotoConsole, launchBrowser, openApiValidator, openConsole, sourceDir, startDaemon, waitFor,
} from './daemon.mjs';

const artifacts = process.env.CORRIDOR_ARTIFACTS ?? join(sourceDir, 'tests/artifacts');

let daemon;
let browser;

before(async () => {
  daemon = await startDaemon();
  browser = await launchBrowser();
});

after(async () => {
  await browser?.close();
  await daemon?.stop();
});

function parsePose(text) {
  const m = /x (-?[\d.]+) m, y (-?[\d.]+) m, (-?[\d.]+)°/.exec(text);
  assert.ok(m, `pose text '${text}'`);
  return { x: Number(m[1]), y: Number(m[2]), yawDeg: Number(m[3]) };
}

// Holds `key` down until the pose the console shows satisfies `done` (up to 10 s), then lets go; `held` runs once
// the key is down.
async function holdKeyUntil(page, key, done, what, held = async () => {}) {
  await page.keyboard.down(key);
  try {
    await held();
    await waitFor(async () => parsePose(await page.getByTestId('pose').textContent()), done, 10000,
      `holding ${key}: ${what}`);
  } finally {
    await page.keyboard.up(key);
  }
}

test('open the console, see the map and the robot, drive with the keyboard', async () => {
  // Connected, the map image loaded, the robot drawn, telemetry live.
  const { page, errors } = await openConsole(browser, daemon.url);
  await page.waitForFunction(() => {
    const img = document.querySelector('img.map-image');
    return img instanceof HTMLImageElement && img.complete && img.naturalWidth === 1165;
  }, null, { timeout: 15000 });
  await page.waitForSelector('path.robot', { timeout: 15000 });
  await page.getByTestId('pose').filter({ hasText: 'x ' }).waitFor();
  await page.waitForFunction(() => document.querySelectorAll('[data-testid=nodes] tbody tr').length === 13);
  // The simulator's three devices, each ok with its rate.
  await page.waitForFunction(() => [...document.querySelectorAll('[data-testid=devices] tbody tr')]
    .filter((tr) => tr.children[1]?.textContent === 'ok' && tr.children[3]?.textContent === 'sim').length === 3);
  await page.waitForFunction(() => {
    const img = document.querySelector('[data-testid=camera]');
    return img instanceof HTMLImageElement && img.complete && img.naturalWidth === 320;
  }, null, { timeout: 15000 });
  await page.getByTestId('lanes').filter({ hasText: /^10 lanes, nearest dead-end/ }).waitFor({ timeout: 10000 });
  const start = parsePose(await page.getByTestId('pose').textContent());
  assert.ok(Math.abs(start.yawDeg - 90) < 1, 'starts facing +y');

  // Hold the up arrow: the robot drives forward (+y); release: it stops.
  await page.getByRole('heading', { name: 'Telemetry' }).click();  // the page has the keys, no control does
  await holdKeyUntil(page, 'ArrowUp', (pose) => pose.y > start.y + 0.35, 'driven 0.35 m forward',
    () => page.getByTestId('mode').filter({ hasText: 'teleop' }).waitFor({ timeout: 5000 }));
  await page.getByTestId('mode').filter({ hasText: 'idle' }).waitFor({ timeout: 5000 });
  await page.getByTestId('speed').filter({ hasText: /^0\.00 m\/s/ }).waitFor({ timeout: 5000 });
  const driven = parsePose(await page.getByTestId('pose').textContent());
  assert.ok(driven.y - start.y > 0.3, `moved from y ${start.y} to ${driven.y}`);
  assert.ok(Math.abs(driven.x - start.x) < 0.1, 'straight ahead');

  // D turns right (clockwise).
  await holdKeyUntil(page, 'd', (pose) => pose.yawDeg < driven.yawDeg - 12, 'turned 12 degrees right');
  await page.getByTestId('mode').filter({ hasText: 'idle' }).waitFor({ timeout: 5000 });
  const turned = parsePose(await page.getByTestId('pose').textContent());
  assert.ok(turned.yawDeg < driven.yawDeg - 10, `turned from ${driven.yawDeg} to ${turned.yawDeg}`);

  mkdirSync(artifacts, { recursive: true });
  await page.screenshot({ path: join(artifacts, 'console.png') });
  assert.deepEqual(errors, []);
});

test('the API page renders the daemon\'s own document, every operation under its tag, without logging in', async () => {
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('requestfailed', (r) => errors.push(`${r.url()}: ${r.failure()?.errorText}`));
  await page.goto(`${daemon.url}/api/docs`);
  const { doc } = openApiValidator();
  await page.waitForFunction((n) => document.querySelectorAll('.opblock-tag-section').length === n, doc.tags.length,
    { timeout: 15000 });
  const operations = Object.values(doc.paths).flatMap((item) => Object.keys(item)).length;
  assert.equal(await page.locator('.opblock').count(), operations);
  // An operation opens on its description.
  await page.locator('.opblock-summary', { hasText: 'Start a mission' }).first().click();
  await page.getByText('Every waypoint is checked first').waitFor({ timeout: 5000 });
  mkdirSync(artifacts, { recursive: true });
  await page.screenshot({ path: join(artifacts, 'api-docs.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

test('the connection indicator shows a lost daemon and reconnects by itself', async () => {
  // The same state directory: the browser's session is kept across the restart.
  const stateDir = mkdtempSync(join(tmpdir(), 'corridor-test-'));
  const first = await startDaemon({ stateDir });
  const page = await browser.newPage();
  await gotoConsole(page, first.url);
  // The daemon goes away (a restart, a crash): the console says so.
  await first.stop();
  await page.getByTestId('connection').filter({ hasText: 'reconnecting' }).waitFor({ timeout: 15000 });
  // It comes back on the same port: the console reconnects without a reload and shows live state again.
  const second = await startDaemon({ stateDir, args: ['--port', String(first.port)] });
  try {
    await page.getByTestId('connection').filter({ hasText: 'connected' }).waitFor({ timeout: 15000 });
    await page.getByTestId('mode').filter({ hasText: 'idle' }).waitFor({ timeout: 5000 });
  } finally {
    await second.stop();
    rmSync(stateDir, { recursive: true, force: true });
  }
});
