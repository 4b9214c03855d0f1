// The console's pages for everyone (issue 39): axe-core (@axe-core/playwright) finds no serious or critical
// accessibility violation on the console, the admin, settings and face pages, at the three sizes the console is used at
// (a desktop, a tablet and a phone with touch), with each of the phone's panels, menus and the map's legend open as
// well as closed. Screenshots of each size are saved with the test's artifacts.
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { after, before, test } from 'node:test';

import { gotoConsole, launchBrowser, require, sourceDir, startDaemon } from './daemon.mjs';

const { AxeBuilder } = require('@axe-core/playwright');
const artifacts = process.env.CORRIDOR_ARTIFACTS ?? join(sourceDir, 'tests/artifacts');

const kSizes = [
  { name: 'desktop', viewport: { width: 1280, height: 800 }, touch: false },
  { name: 'tablet', viewport: { width: 1024, height: 768 }, touch: true },
  { name: 'phone', viewport: { width: 390, height: 844 }, touch: true },
];
const kSheets = ['mission', 'drive', 'camera', 'robot', 'map', 'events'];

let daemon;
let browser;

before(async () => {
  daemon = await startDaemon();
  browser = await launchBrowser();
  mkdirSync(artifacts, { recursive: true });
});

after(async () => {
  await browser?.close();
  await daemon?.stop();
});

// The serious and critical violations on the page as it is now, each with where it was found.
async function violations(page, where) {
  const result = await new AxeBuilder({ page }).analyze();
  return result.violations.filter((v) => v.impact === 'serious' || v.impact === 'critical')
    .map((v) => `${where}: ${v.id} (${v.impact}) at ${v.nodes.map((n) => n.target.join(' ')).slice(0, 3).join(', ')}`);
}

for (const size of kSizes) {
  test(`${size.name}: no serious or critical accessibility violation on the console, admin, settings and face pages`, async () => {
    const context = await browser.newContext({ viewport: size.viewport, hasTouch: size.touch, isMobile: size.touch });
    const page = await context.newPage();
    try {
      await gotoConsole(page, daemon.url);
      await page.waitForFunction(() => window.corridorConsole !== undefined);
      await page.getByTestId('mode').filter({ hasText: 'idle' }).waitFor();
      const found = [];
      found.push(...await violations(page, 'console'));
      await page.screenshot({ path: join(artifacts, `console-${size.name}.png`) });
      await page.getByTestId('legend-toggle').click();
      found.push(...await violations(page, 'console with the legend'));
      await page.getByTestId('legend-toggle').click();
      if (size.viewport.width <= 700) {
        await page.getByTestId('tools-toggle').click();
        found.push(...await violations(page, 'console with the tools menu'));
        await page.getByTestId('tools-toggle').click();
        await page.getByTestId('menu-toggle').click();
        found.push(...await violations(page, 'console with the menu'));
        await page.getByTestId('menu-toggle').click();
        for (const sheet of kSheets) {
          await page.getByTestId(`sheet-${sheet}`).click();
          found.push(...await violations(page, `console's ${sheet} sheet`));
          if (sheet === 'mission') await page.screenshot({ path: join(artifacts, `console-${size.name}-sheet.png`) });
        }
      }
      await page.goto(`${daemon.url}/admin`);
      await page.getByTestId('users').filter({ hasText: 'tester' }).waitFor();
      found.push(...await violations(page, 'admin'));
      await page.goto(`${daemon.url}/settings`);
      await page.locator('details[data-section=safety] summary').click();
      await page.locator('.setting[data-path="safety.max_linear_mps"] input').waitFor();
      found.push(...await violations(page, 'settings'));
      await page.screenshot({ path: join(artifacts, `settings-${size.name}.png`) });
      await page.goto(`${daemon.url}/face`);
      await page.locator('canvas').first().waitFor();
      found.push(...await violations(page, 'face'));
      assert.deepEqual(found, []);
    } finally {
      await context.close();
    }
  });
}
