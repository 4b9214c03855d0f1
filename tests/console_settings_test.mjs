// The settings page (issue 39) at the three sizes the console is used at, in a real browser against a real corridord
// with a configuration file of its own: a setting found by searching, refused by the daemon with its reason shown by
// its field (and the file left as it was), changed, marked as taking effect at the next start, a choice changed, and
// both put back to their defaults.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';

import { getJson, gotoConsole, launchBrowser, sourceDir, startDaemon } from './daemon.mjs';

const kSizes = [
  { name: 'desktop', viewport: { width: 1280, height: 800 }, touch: false, level: 'debug' },
  { name: 'tablet', viewport: { width: 1024, height: 768 }, touch: true, level: 'warn' },
  { name: 'phone', viewport: { width: 390, height: 844 }, touch: true, level: 'error' },
];
// A small world and a small camera: the page is what is tested, not the robot.
const config = `sim: {world: "${sourceDir}tests/data/maps/lse_arena/lse_arena.yaml", start: {x_m: 1.0, y_m: 0.75},
  camera: {width: 160, height: 120}}
devices: {laser: {driver: none}}
`;

let daemon;
let browser;

before(async () => {
  daemon = await startDaemon({ config });
  browser = await launchBrowser();
});

after(async () => {
  await browser?.close();
  await daemon?.stop();
});

const fileConfig = async () => (await getJson(`${daemon.url}/api/v1/config`)).body;

for (const size of kSizes) {
  test(`${size.name}: a setting refused by the field, changed for the next start, and put back`, async () => {
    const context = await browser.newContext({ viewport: size.viewport, hasTouch: size.touch, isMobile: size.touch });
    const page = await context.newPage();
    const errors = [];
    page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
    // The refusal is a 422 the page asked for; anything else failing is an error.
    page.on('response', (r) => {
      if (r.status() >= 400 && !(r.status() === 422 && r.url().endsWith('/api/v1/config'))) {
        errors.push(`${r.status()} ${r.request().method()} ${r.url()}`);
      }
    });
    try {
      await gotoConsole(page, daemon.url);
      if (size.viewport.width <= 700) await page.getByTestId('menu-toggle').click();
      await page.getByTestId('settings-link').click();
      await page.getByTestId('settings-file').filter({ hasText: 'corridor.yaml' }).waitFor();

      // Found by a word of its help; out of range, refused by the daemon with the reason by the field.
      await page.getByTestId('settings-search').fill('lapses after');
      const deadman = page.locator('.setting[data-path="safety.teleop_deadman_s"]');
      await deadman.waitFor({ state: 'visible' });
      assert.equal(await page.locator('.setting[data-path="safety.max_linear_mps"]').isVisible(), false, 'filtered');
      await page.getByTestId('settings-search').fill('');
      const row = page.locator('.setting[data-path="safety.max_linear_mps"]');
      assert.match(await row.locator('.help').textContent(), /default 0\.5 · from 0 to 3/);
      await row.locator('input').fill('5');
      await page.getByTestId('settings-save').click();
      await row.locator('.error').filter({ hasText: 'must be between 0 and 3' }).waitFor({ timeout: 5000 });
      assert.equal(await row.locator('input').getAttribute('aria-invalid'), 'true');
      assert.match(await page.getByTestId('settings-status').textContent(), /Not saved/);
      assert.equal((await fileConfig()).config.safety?.max_linear_mps, undefined, 'the file is left as it was');

      // In range: written, and marked as taking effect at the next start.
      await row.locator('input').fill('0.4');
      assert.equal(await row.locator('.error').textContent(), '', 'the error goes as the field is changed');
      await page.getByTestId('settings-save').click();
      await page.getByTestId('settings-status').filter({ hasText: 'takes effect at the next start' }).waitFor();
      await row.locator('.pending-tag').filter({ hasText: 'at next start' }).waitFor();
      let saved = await fileConfig();
      assert.equal(saved.config.safety.max_linear_mps, 0.4);
      assert.ok(saved.pending.includes('safety.max_linear_mps'), JSON.stringify(saved.pending));
      await page.getByTestId('settings-pending').filter({ hasText: 'safety.max_linear_mps' }).waitFor();

      // A choice.
      await page.locator('details[data-section=log] summary').click();
      await page.locator('.setting[data-path="log.level"] select').selectOption(size.level);
      await page.getByTestId('settings-save').click();
      await page.getByTestId('settings-status').filter({ hasText: 'Saved log.level' }).waitFor();
      assert.equal((await fileConfig()).config.log.level, size.level);

      // Both back to their defaults: the keys leave the file, nothing is pending.
      await row.getByRole('button', { name: 'safety.max_linear_mps: back to the default' }).click();
      await page.locator('.setting[data-path="log.level"]')
        .getByRole('button', { name: 'log.level: back to the default' }).click();
      await page.getByTestId('settings-save').click();
      await page.getByTestId('settings-status').filter({ hasText: /^Saved/ }).waitFor();
      saved = await fileConfig();
      assert.equal(saved.config.safety?.max_linear_mps, undefined, JSON.stringify(saved.config));
      assert.equal(saved.config.log?.level, undefined);
      assert.deepEqual(saved.pending, []);
      assert.equal(await page.getByTestId('settings-pending').isHidden(), true);
      assert.deepEqual(errors, []);
    } finally {
      await context.close();
    }
  });
}
