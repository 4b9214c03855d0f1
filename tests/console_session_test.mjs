// The console as people use it, at the three sizes it is used at: a desktop with a mouse (1280 x 800), a tablet with
// touch (1024 x 768) and a phone with touch (390 x 844), in a real browser against a real corridord.
// What is checked is what the console sends and shows: the teleop commands the keys and the joystick send (read off the
// WebSocket), and that a session leaves no error in the browser's console.
import assert from 'node:assert/strict';
import { after, before, test } from 'node:test';

import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import { getJson, gotoConsole, launchBrowser, sendJson, sourceDir, startDaemon, waitFor } from './daemon.mjs';

const kSizes = [
  { name: 'desktop', viewport: { width: 1280, height: 800 }, touch: false },
  { name: 'tablet', viewport: { width: 1024, height: 768 }, touch: true },
  { name: 'phone', viewport: { width: 390, height: 844 }, touch: true },
];

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

// A logged-in console at `size`; `sent` holds every teleop command the page has sent on the stream, in order.
async function openAt(size) {
  const context = await browser.newContext({ viewport: size.viewport, hasTouch: size.touch, isMobile: size.touch });
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(`page error: ${e.message}`));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
  // A request the console makes that fails is an error too (Chromium logs most of them; this names them all).
  page.on('response', (r) => { if (r.status() >= 400) errors.push(`${r.status()} ${r.request().method()} ${r.url()}`); });
  const sent = [];
  page.on('websocket', (ws) => ws.on('framesent', ({ payload }) => {
    if (typeof payload !== 'string') return;
    const message = JSON.parse(payload);
    if (message.type === 'teleop') sent.push(message);
  }));
  await gotoConsole(page, daemon.url);
  return { context, page, errors, sent };
}

// The first teleop command sent after `count` commands that satisfies `predicate`, waiting for it up to 10 s (the
// console sends ten a second while something is held; a loaded machine can hold the browser up for seconds). A failure
// says what the page showed: its stream's state and whether the joystick had the pointer.
async function nextCommand(page, sent, count, predicate, what) {
  const end = Date.now() + 10000;
  for (;;) {
    const found = sent.slice(count).find(predicate);
    if (found) return found;
    if (Date.now() > end) {
      const connection = await page.getByTestId('connection').textContent();
      const knob = await page.locator('.joystick-knob').first().evaluate((e) => e.style.transform);
      throw new Error(`no teleop command ${what}; sent after: ${JSON.stringify(sent.slice(count).slice(-5))}; ` +
        `stream ${connection}, joystick knob '${knob}'`);
    }
    await new Promise((r) => setTimeout(r, 20));
  }
}

const isStop = (c) => c.linear_mps === 0 && c.angular_rps === 0;

// The element's box once it stays where it is from one frame to the next: a column scrolled to show it may still be
// moving it (smooth scrolling), and a drag from a stale centre would point somewhere else.
async function settledBox(locator) {
  let box = await locator.boundingBox();
  const end = Date.now() + 3000;
  for (;;) {
    await locator.evaluate(() => new Promise((resolve) => requestAnimationFrame(() => resolve())));
    const now = await locator.boundingBox();
    if ((now.x === box.x && now.y === box.y) || Date.now() > end) return now;
    box = now;
  }
}

// Presses the joystick's centre, drags (dx, dy) pixels, reads the command that drag sends, and releases: with the
// mouse, or with a finger through the DevTools protocol (Playwright's touchscreen only taps).
async function drag(page, touch, dx, dy) {
  const box = await settledBox(page.getByTestId('joystick'));
  const x = box.x + box.width / 2;
  const y = box.y + box.height / 2;
  if (!touch) {
    await page.mouse.move(x, y);
    await page.mouse.down();
    await page.mouse.move(x + dx, y + dy, { steps: 4 });
    return async () => page.mouse.up();
  }
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [{ x, y }] });
  for (let i = 1; i <= 4; ++i) {
    await cdp.send('Input.dispatchTouchEvent',
      { type: 'touchMove', touchPoints: [{ x: x + (dx * i) / 4, y: y + (dy * i) / 4 }] });
  }
  return async () => {
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
    await cdp.detach();
  };
}

// Drags the joystick up, down, left and right by 80 px (past its 60 px ring) and checks each command: full speed the
// way it points, nothing the other way; a stop on each release.
async function dragFourWays(page, sent, touch, where) {
  const ways = [
    { name: 'up', dx: 0, dy: -80, want: (c) => c.linear_mps > 0.35 && Math.abs(c.angular_rps) < 0.05 },
    { name: 'down', dx: 0, dy: 80, want: (c) => c.linear_mps < -0.35 && Math.abs(c.angular_rps) < 0.05 },
    { name: 'left', dx: -80, dy: 0, want: (c) => c.angular_rps > 0.9 && Math.abs(c.linear_mps) < 0.02 },
    { name: 'right', dx: 80, dy: 0, want: (c) => c.angular_rps < -0.9 && Math.abs(c.linear_mps) < 0.02 },
  ];
  for (const way of ways) {
    const count = sent.length;
    const release = await drag(page, touch, way.dx, way.dy);
    // Where the finger stops is what the robot is told while it stays there: full speed that way.
    await nextCommand(page, sent, count, way.want, `dragging ${way.name} (${where})`);
    const before = sent.length;
    await release();
    await nextCommand(page, sent, before, isStop, `stop after releasing ${way.name} (${where})`);
  }
}

// Whether the page has the phone's layout (style.css: 700 px wide or less): the panels a sheet of tabs, the tools and
// the account a menu each.
function isPhone(page) {
  return page.viewportSize().width <= 700;
}

// Shows the panels of sheet tab `sheet` (mission, drive, camera, robot, map): on a phone its tab opens the sheet; on a
// wider screen every panel is in the column already.
async function showPanel(page, sheet) {
  if (!isPhone(page)) return;
  const tab = page.getByTestId(`sheet-${sheet}`);
  const selected = await tab.getAttribute('aria-selected') === 'true';
  const open = await page.getByTestId('panels').evaluate((e) => e.classList.contains('expanded'));
  if (!(selected && open)) await tab.click();
}

// Brings the joystick into view (a phone's Drive tab, or the side column scrolled down to it): it moves on the
// screen after it was made. Returns how far the column or the page scrolled.
async function reachJoystick(page) {
  await showPanel(page, 'drive');
  await page.getByTestId('joystick').scrollIntoViewIfNeeded();
  return page.evaluate(() => (document.querySelector('aside')?.scrollTop ?? 0) + window.scrollY);
}

for (const size of kSizes) {
  test(`${size.name}: the keys and the joystick command what they point at, scrolled, resized and turned`, async () => {
    const { context, page, errors, sent } = await openAt(size);
    try {
      // The map is the first thing anyone clicks; the arrow keys still drive after it (they do not pan the map).
      await page.getByTestId('map').click({ position: { x: 30, y: 200 } });
      let count = sent.length;
      await page.keyboard.down('ArrowUp');
      const up = await nextCommand(page, sent, count, (c) => !isStop(c), 'for the up arrow after clicking the map');
      assert.deepEqual([up.linear_mps, up.angular_rps], [0.4, 0]);
      count = sent.length;
      await page.keyboard.up('ArrowUp');
      await nextCommand(page, sent, count, isStop, 'stop on releasing the up arrow');
      count = sent.length;
      await page.keyboard.down('ArrowLeft');
      const left = await nextCommand(page, sent, count, (c) => !isStop(c), 'for the left arrow');
      assert.deepEqual([left.linear_mps, left.angular_rps], [0, 1]);
      await page.keyboard.up('ArrowLeft');
      // In a text field the keys type and do not drive.
      await showPanel(page, 'map');
      await page.getByTestId('mapping-name').focus();
      count = sent.length;
      await page.keyboard.press('ArrowDown');
      await page.keyboard.type('sd');
      assert.equal(await page.getByTestId('mapping-name').inputValue(), 'sd');
      assert.deepEqual(sent.slice(count).filter((c) => !isStop(c)), [], 'keys in a text field sent commands');
      await page.getByTestId('mapping-name').fill('');

      // The joystick is below the fold on a wider screen (the column scrolls to reach it) and on its own tab on a
      // phone (the sheet opens to show it): either way it moved after it was made.
      const scrolled = await reachJoystick(page);
      if (!isPhone(page)) assert.ok(scrolled > 0, 'the joystick was reached without scrolling');
      await dragFourWays(page, sent, size.touch, 'after reaching it');
      // A resize, or the phone or tablet turned (a phone on its side has the tablet's layout): the joystick moves
      // again.
      await page.setViewportSize({ width: size.viewport.height, height: size.viewport.width });
      await reachJoystick(page);
      await dragFourWays(page, sent, size.touch, 'after turning the screen');
      assert.deepEqual(errors, []);
    } finally {
      await context.close();
    }
  });
}

// The page coordinates of a map-frame point, with the map centred on it at `zoom` first (on a phone the map is small).
async function showAt(page, x, y, zoom = 6) {
  return page.evaluate(([px, py, z]) => {
    const { map } = window.corridorConsole.view;
    map.setView([py, px], z, { animate: false });
    const p = map.latLngToContainerPoint([py, px]);
    const box = map.getContainer().getBoundingClientRect();
    return { x: box.left + p.x, y: box.top + p.y, scale: 2 ** z };
  }, [x, y, zoom]);
}

// Picks map tool `name`: on a phone from the tools' menu (which closes it, and the sheet, to leave the map free).
async function tool(page, name) {
  if (isPhone(page)) await page.getByTestId('tools-toggle').click();
  const button = page.getByTestId('tools').getByRole('button', { name, exact: true });
  await button.scrollIntoViewIfNeeded();
  await button.click();
}

// Presses at page point `from`, drags to `to` and lets go: with the mouse, or with a finger through the DevTools
// protocol.
async function dragOnPage(page, touch, from, to) {
  if (!touch) {
    await page.mouse.move(from.x, from.y);
    await page.mouse.down();
    await page.mouse.move(to.x, to.y, { steps: 6 });
    await page.mouse.up();
    return;
  }
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchStart', touchPoints: [from] });
  for (let i = 1; i <= 6; ++i) {
    await cdp.send('Input.dispatchTouchEvent', { type: 'touchMove',
      touchPoints: [{ x: from.x + ((to.x - from.x) * i) / 6, y: from.y + ((to.y - from.y) * i) / 6 }] });
  }
  await cdp.send('Input.dispatchTouchEvent', { type: 'touchEnd', touchPoints: [] });
  await cdp.detach();
}

// Issue 39: every drag tool works with a finger as with a mouse, and the stop button is there at every size.
for (const size of kSizes) {
  test(`${size.name}: a goal dragged for its heading, driven, and stopped with one tap`, async () => {
    const { context, page, errors } = await openAt(size);
    try {
      await page.waitForFunction(() => window.corridorConsole !== undefined);
      await tool(page, 'Go to');
      // Pressed at the goal, dragged 1 m towards -x: the goal faces west.
      const goal = await showAt(page, 23.4, 24.3);
      await dragOnPage(page, size.touch, goal, { x: goal.x - goal.scale, y: goal.y });
      await page.getByTestId('plan-summary').filter({ hasText: /m, clearance/ }).waitFor({ timeout: 10000 });
      const yaw = await page.evaluate(() => window.corridorConsole.tools.goal.yaw);
      assert.ok(Math.abs(Math.abs(yaw) - Math.PI) < 0.1, `the goal faces ${yaw}`);
      await page.getByTestId('plan-go').click();
      await waitFor(async () => (await getJson(`${daemon.url}/api/v1/state`)).body,
        (s) => s.mission?.status === 'active' && Math.abs(s.velocity.linear_mps) > 0.05, 10000, 'driving to the goal');
      // The stop button, always in the header: the robot stops and the mission waits, paused.
      await page.getByTestId('estop').click();
      await showPanel(page, 'mission');
      await page.getByTestId('mission-status').filter({ hasText: /^paused/ }).waitFor({ timeout: 5000 });
      await waitFor(async () => (await getJson(`${daemon.url}/api/v1/state`)).body,
        (s) => Math.abs(s.velocity.linear_mps) < 0.01 && Math.abs(s.velocity.angular_rps) < 0.01, 5000, 'stopped');
      await page.getByTestId('message').filter({ hasText: 'mission paused' }).waitFor({ timeout: 5000 });
      await page.locator('#mission-cancel').click();
      await page.getByTestId('mission-status').filter({ hasText: /^canceled/ }).waitFor({ timeout: 5000 });
      // The laser's scan is on the map, and the legend says what the dots are.
      await page.waitForFunction(() => window.corridorConsole.view.scan.getLayers().length > 100, null,
        { timeout: 5000 });
      await page.getByTestId('legend-toggle').click();
      await page.getByTestId('legend').getByText('the laser\'s scan').waitFor();
      assert.deepEqual(errors, []);
    } finally {
      await context.close();
    }
  });
}

// Issue 39: the robot's events reach people as notifications and in a history they can filter, a failed mission says
// why, and the face can be set and made to speak from the console, at every size.
for (const size of kSizes) {
  test(`${size.name}: events arrive as notifications and in the history; the face shows and says what it is told`,
    async () => {
      const { context, page, errors } = await openAt(size);
      try {
        await page.waitForFunction(() => window.corridorConsole !== undefined);
        // Half a metre to a metre away, the other way each time (every size drives the same robot).
        const goal = size.name === 'tablet' ? { x: 23.4, y: 24.3 } : { x: 24.4, y: 24.6 };
        const started = await sendJson('POST', `${daemon.url}/api/v1/missions`, { waypoints: [goal] });
        assert.equal(started.status, 201, JSON.stringify(started.body));
        await page.getByTestId('toasts').locator('.toast[data-type=mission_succeeded]')
          .filter({ hasText: 'done' }).waitFor({ timeout: 30000 });
        await showPanel(page, 'events');
        const list = page.getByTestId('events-list');
        await list.locator('[data-type=mission_succeeded]').first().waitFor();
        await page.getByTestId('events-filter').selectOption('people');
        assert.equal(await list.locator('[data-type=mission_succeeded]').count(), 0, 'filtered out');
        await page.getByTestId('events-filter').selectOption('missions');
        await list.locator('[data-type=mission_succeeded]').first().waitFor();

        // The plots have been sampling the state all along: the mission's speed (forward or backing) is in them.
        await showPanel(page, 'robot');
        await page.getByTestId('plots').locator('.plot canvas').first().waitFor();
        assert.equal(await page.getByTestId('plots').locator('.plot').count(), 5);
        const speeds = await page.evaluate(() => window.corridorConsole.plots.values[0][1]);
        assert.ok(speeds.some((v) => Math.abs(v) > 0.1), `measured speeds plotted: ${JSON.stringify(speeds)}`);
        await page.getByTestId('face-expression').selectOption('surprised');
        await page.getByTestId('face-show').click();
        await page.getByTestId('face-now').filter({ hasText: 'surprised' }).waitFor({ timeout: 5000 });
        await page.getByTestId('face-say').fill('Excuse me, coming through');
        await page.getByTestId('face-speak').click();
        await waitFor(async () => (await getJson(`${daemon.url}/api/v1/face`)).body.said,
          (said) => said === 'Excuse me, coming through', 5000, 'the phrase said');

        // A mission that cannot be done says why: in a notification, and on the Mission tab.
        const island = { x: 12.73, y: 27.12 };  // free floor, but walled in on the map: no path reaches it
        const doomed = await sendJson('POST', `${daemon.url}/api/v1/missions`, { waypoints: [island] });
        assert.equal(doomed.status, 201, JSON.stringify(doomed.body));
        await page.getByTestId('toasts').locator('.toast[data-type=mission_failed]').filter({ hasText: 'no path' })
          .waitFor({ timeout: 15000 });
        await showPanel(page, 'mission');
        await page.getByTestId('mission-status').filter({ hasText: /^failed: no path from/ }).waitFor({ timeout: 5000 });
        assert.deepEqual(errors, []);
      } finally {
        await context.close();
      }
    });
}

// Issue 39: the map library from the console at every size: a map exported as a zip of map_server files and imported
// from it, another imported from its .yaml and image, one renamed, both deleted.
for (const size of kSizes) {
  test(`${size.name}: maps exported, imported, renamed and deleted from the console`, async () => {
    const { context, page, errors } = await openAt(size);
    const library = page.getByTestId('maps-list');
    const row = (name) => library.locator(`li[data-map="${name}"]`);
    const names = async () => (await getJson(`${daemon.url}/api/v1/maps`)).body.maps;
    const exportDir = mkdtempSync(join(tmpdir(), 'corridor-export-'));
    try {
      await showPanel(page, 'map');
      await row('willow-full-0.05').waitFor();
      const [download] = await Promise.all([page.waitForEvent('download'),
        row('willow-full-0.05').locator('[data-action=export]').click()]);
      assert.equal(download.suggestedFilename(), 'willow-full-0.05.zip');

      // The zip imported under a name of its own; the name proposed is the zip's.
      const copy = `copy-${size.name}`;
      const zip = join(exportDir, download.suggestedFilename());
      await download.saveAs(zip);
      await page.getByTestId('maps-import-files').setInputFiles(zip);
      assert.equal(await page.getByTestId('maps-import-name').inputValue(), 'willow-full-0.05');
      await page.getByTestId('maps-import-name').fill(copy);
      await page.getByTestId('maps-import').click();
      await row(copy).waitFor({ timeout: 10000 });
      assert.equal(await page.getByTestId('maps-import-name').inputValue(), '', 'the form is emptied');

      // A .yaml and its image, chosen together.
      const arena = join(sourceDir, 'tests/data/maps/lse_arena');
      await page.getByTestId('maps-import-files').setInputFiles(
        [join(arena, 'lse_arena.yaml'), join(arena, 'lse_arena.pgm')]);
      await page.getByTestId('maps-import-name').fill(`arena-${size.name}`);
      await page.getByTestId('maps-import').click();
      await row(`arena-${size.name}`).waitFor({ timeout: 10000 });

      // Renamed in place (Enter), then both deleted (confirmed).
      await row(copy).locator('[data-action=rename]').click();
      const field = library.getByRole('textbox', { name: `new name for map ${copy}` });
      await field.fill(`${copy}-b`);
      await field.press('Enter');
      await row(`${copy}-b`).waitFor({ timeout: 5000 });
      assert.ok(!(await names()).includes(copy));
      page.on('dialog', (dialog) => void dialog.accept());
      for (const name of [`${copy}-b`, `arena-${size.name}`]) {
        await row(name).locator('[data-action=delete]').click();
        await row(name).waitFor({ state: 'detached', timeout: 5000 });
      }
      assert.deepEqual((await names()).filter((n) => n.endsWith(size.name)), []);
      assert.deepEqual(errors, []);
    } finally {
      await context.close();
      rmSync(exportDir, { recursive: true, force: true });
    }
  });
}

// Issue 36, done when: a normal session (log in, drive with keys and joystick, send a goal and go to a place, draw a
// zone, dock, map and stop mapping, log out) at each of the three sizes leaves no error in the browser's console and
// no failed request.
for (const size of kSizes) {
  test(`${size.name}: a whole session leaves no error in the browser's console`, async () => {
    const { context, page, errors, sent } = await openAt(size);
    const url = daemon.url;
    const message = page.getByTestId('message');
    try {
      await page.waitForFunction(() => window.corridorConsole !== undefined);
      await showPanel(page, 'robot');
      await page.getByTestId('pose').filter({ hasText: 'x ' }).waitFor();
      // Drive: a key, then the joystick.
      await page.getByTestId('map').click({ position: { x: 30, y: 200 } });
      await page.keyboard.down('ArrowLeft');
      await nextCommand(page, sent, 0, (c) => c.angular_rps > 0, 'for the left arrow');
      await page.keyboard.up('ArrowLeft');
      await reachJoystick(page);
      const count = sent.length;
      const release = await drag(page, size.touch, 0, -40);
      await nextCommand(page, sent, count, (c) => c.linear_mps > 0, 'for the joystick pushed up');
      await release();
      await page.getByTestId('mode').filter({ hasText: 'idle' }).waitFor({ timeout: 5000 });

      // A goal: previewed, driven, cancelled.
      await tool(page, 'Go to');
      const goal = await showAt(page, 23.4, 24.3);
      await page.mouse.click(goal.x, goal.y);
      await page.getByTestId('plan-summary').filter({ hasText: /m, clearance/ }).waitFor({ timeout: 10000 });
      await page.getByTestId('plan-go').click();
      await showPanel(page, 'mission');
      await page.getByTestId('mission-status').filter({ hasText: /^active/ }).waitFor({ timeout: 5000 });
      await page.locator('#mission-cancel').click();
      await page.getByTestId('mission-status').filter({ hasText: /^canceled/ }).waitFor({ timeout: 5000 });

      // A no-go zone, deleted, put back with Undo, then deleted for good.
      await tool(page, 'No-go zone');
      const corners = [[25.2, 24.2], [25.6, 24.2], [25.6, 24.6], [25.2, 24.6], [25.2, 24.2]];
      const centre = await showAt(page, 25.4, 24.4, 7);
      for (const [x, y] of corners) {
        await page.mouse.click(centre.x + (x - 25.4) * centre.scale, centre.y - (y - 24.4) * centre.scale);
      }
      await message.filter({ hasText: 'no-go zone added' }).waitFor({ timeout: 10000 });
      await tool(page, 'Delete zone');
      await page.mouse.click(centre.x, centre.y);
      await message.filter({ hasText: /zone 'no-go' deleted/ }).waitFor({ timeout: 5000 });
      await page.getByTestId('message-undo').click();
      await message.filter({ hasText: /restored/ }).waitFor({ timeout: 5000 });
      assert.equal((await getJson(`${url}/api/v1/zones`)).body.zones.length, 1);
      await page.mouse.click(centre.x, centre.y);
      await message.filter({ hasText: /zone 'no-go' deleted/ }).waitFor({ timeout: 5000 });
      assert.equal((await getJson(`${url}/api/v1/zones`)).body.zones.length, 0);
      await tool(page, 'Pan');

      // A named place, chosen on the Mission tab: the mission to it starts, then is cancelled.
      await showPanel(page, 'mission');
      await page.getByTestId('places').selectOption('dock');
      await page.locator('#place-go').click();
      await page.getByTestId('mission-status').filter({ hasText: /^active/ }).waitFor({ timeout: 10000 });
      assert.equal((await getJson(`${url}/api/v1/state`)).body.mission.waypoints.at(-1).place, 'dock');
      await page.locator('#mission-cancel').click();
      await page.getByTestId('mission-status').filter({ hasText: /^canceled/ }).waitFor({ timeout: 5000 });

      // Dock: the mission starts (issue 36: it was refused in this world), then cancelled.
      await page.getByTestId('dock').scrollIntoViewIfNeeded();
      await page.getByTestId('dock').click();
      await page.getByTestId('mission-status').filter({ hasText: /^active/ }).waitFor({ timeout: 10000 });
      await page.locator('#mission-cancel').click();
      await page.getByTestId('mission-status').filter({ hasText: /^canceled/ }).waitFor({ timeout: 5000 });

      // Map while turning on the spot, stop: the new map is in use and the building's map is still there.
      const name = `session-${size.name}`;
      await showPanel(page, 'map');
      await page.getByTestId('mapping-name').fill(name);
      await page.getByTestId('mapping-start').click();
      await page.getByTestId('mapping-status').filter({ hasText: new RegExp(`^mapping '${name}': [1-9]`) })
        .waitFor({ timeout: 10000 });
      await page.locator('body').click({ position: { x: 1, y: 1 } });
      // Turning: the key held until the robot has turned about a radian.
      const yaw = async () => (await getJson(`${url}/api/v1/state`)).body.sim_true_pose.yaw;
      const from = await yaw();
      await page.keyboard.down('ArrowLeft');
      await waitFor(yaw, (now) => Math.abs(Math.atan2(Math.sin(now - from), Math.cos(now - from))) > 0.8, 10000,
        'turned while mapping');
      await page.keyboard.up('ArrowLeft');
      await page.getByTestId('mapping-stop').click();
      await page.getByTestId('mapping-status').filter({ hasText: `'${name}' saved and in use` })
        .waitFor({ timeout: 15000 });
      await page.getByTestId('map-in-use').filter({ hasText: name }).waitFor({ timeout: 5000 });
      const maps = (await getJson(`${url}/api/v1/maps`)).body.maps.map((m) => m.name ?? m);
      assert.ok(maps.includes('willow-full-0.05') && maps.includes(name), JSON.stringify(maps));
      // Back to the building's map, chosen in the map library.
      const library = page.getByTestId('maps-list');
      await library.locator(`li[data-map="${name}"] em`).filter({ hasText: 'in use' }).waitFor({ timeout: 5000 });
      await library.locator('li[data-map="willow-full-0.05"] [data-action=use]').click();
      await page.getByTestId('map-in-use').filter({ hasText: 'willow-full-0.05' }).waitFor({ timeout: 5000 });
      await library.locator('li[data-map="willow-full-0.05"] em').filter({ hasText: 'in use' }).waitFor();

      // Log out (on a phone from the header's menu): the login form, and nothing on the page failed along the way.
      if (isPhone(page)) await page.getByTestId('menu-toggle').click();
      await page.getByTestId('logout').click();
      await page.getByTestId('login').waitFor({ state: 'visible', timeout: 10000 });
      assert.deepEqual(errors, []);
    } finally {
      await context.close();
    }
  });
}
