// The face kiosk page's CPU in Chromium on this machine (issue 21: at most 10 % of one core): corridord with the
// simulator, the page at /face at the given screen size, left to run for --seconds while the face idles (blinks only)
// and then while it changes expression every 2 s and follows a person pushed in at a changing bearing. CPU per Chromium
// process from the DevTools protocol (SystemInfo.getProcessInfo), headless with software rendering as in the tests.
//   node bench/face_page_cpu.mjs [--seconds 30] [--width 800 --height 480]
// Needs ./dev build.
import { launchBrowser, postJson, sleep, startDaemon } from '../tests/daemon.mjs';

function option(name, fallback) {
  const i = process.argv.indexOf(name);
  return i > 0 && i + 1 < process.argv.length ? process.argv[i + 1] : fallback;
}
const seconds = Number(option('--seconds', '30'));
const width = Number(option('--width', '800'));
const height = Number(option('--height', '480'));

const daemon = await startDaemon();
const browser = await launchBrowser();
try {
  const page = await browser.newPage({ viewport: { width, height } });
  await page.goto(`${daemon.url}/face`);
  await page.waitForFunction(() => document.body.dataset.connected === 'true', null, { timeout: 10000 });
  const cdp = await browser.newBrowserCDPSession();
  const cpuTimes = async () => {
    const { processInfo } = await cdp.send('SystemInfo.getProcessInfo');
    const byType = new Map();
    for (const p of processInfo) byType.set(p.type, (byType.get(p.type) ?? 0) + p.cpuTime);
    return byType;
  };
  const measure = async (label, during) => {
    const before = await cpuTimes();
    const t0 = Date.now();
    await during();
    const elapsed = (Date.now() - t0) / 1000;
    const after = await cpuTimes();
    let total = 0;
    const parts = [];
    for (const [type, cpu] of after) {
      const used = cpu - (before.get(type) ?? 0);
      total += used;
      parts.push(`${type} ${(100 * used / elapsed).toFixed(1)} %`);
    }
    console.log(`${label} (${width} x ${height}, ${elapsed.toFixed(0)} s): ${(100 * total / elapsed).toFixed(1)} % of one ` +
      `core in all Chromium processes (${parts.join(', ')})`);
  };
  await sleep(2000);
  await measure('idle, blinking', () => sleep(seconds * 1000));
  const expressions = ['happy', 'focused', 'surprised', 'worried', 'sleepy', 'confused', 'sad', 'neutral'];
  await measure('an expression every 2 s, a person moving across', async () => {
    for (let t = 0; t < seconds; t += 2) {
      await postJson(`${daemon.url}/api/v1/face`, { expression: expressions[(t / 2) % expressions.length], hold_s: 2 });
      await postJson(`${daemon.url}/api/v1/detections`, { source: 'bench', ttl_s: 2, detections: [
        { class: 'person', position: { x: 1.5, y: Math.sin(t / 3), z: 0.9 } }] });
      await sleep(2000);
    }
  });
} finally {
  await browser.close();
  await daemon.stop();
}
