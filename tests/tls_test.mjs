// HTTPS and WSS on corridord's port: the self-signed certificate made on first start (its fingerprint in the journal
// and at setup), a configured certificate, the plain-HTTP redirect, Secure cookies, and the console in Chromium
// trusting the certificate by its key's hash.
import assert from 'node:assert/strict';
import { createHash, X509Certificate } from 'node:crypto';
import { mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { request as httpRequest } from 'node:http';
import { request as httpsRequest } from 'node:https';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { after, before, describe, test } from 'node:test';

import {
  authHeaders, consoleUser, gotoConsole, launchBrowser, makeCertificate, require, runCorridord, startDaemon, writeRoom,
} from './daemon.mjs';

const WebSocket = require('ws');
const dir = mkdtempSync(join(tmpdir(), 'corridor-tls-'));
after(() => rmSync(dir, { recursive: true, force: true }));
const room = writeRoom(dir, 4, 3);

const config = (tls) => `
sim:
  world: "${room}"
  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 0}
  camera: {rate_hz: 15, width: 160, height: 120}
server:
  tls:
${Object.entries(tls).map(([k, v]) => `    ${k}: ${JSON.stringify(v)}`).join('\n')}
`;

// A port nobody listens on now.
function freePort() {
  return new Promise((resolve) => {
    const server = createServer().listen(0, '127.0.0.1', () => {
      const { port } = server.address();
      server.close(() => resolve(port));
    });
  });
}

// One request over HTTP or HTTPS (trusting `ca`); resolves {status, headers, body}.
function call(url, { method = 'GET', headers = {}, body, ca } = {}) {
  return new Promise((resolve, reject) => {
    const send = url.startsWith('https:') ? httpsRequest : httpRequest;
    const req = send(url, { method, headers, ca }, (res) => {
      let text = '';
      res.on('data', (d) => { text += d; });
      res.on('end', () => resolve({ status: res.statusCode, headers: res.headers, body: text }));
    });
    req.on('error', reject);
    req.end(body);
  });
}

describe('the generated certificate', () => {
  let daemon;
  let redirectPort;
  let ca;
  let cert;
  before(async () => {
    redirectPort = await freePort();
    daemon = await startDaemon({ config: config({ enabled: true, redirect_port: redirectPort }) });
    ca = readFileSync(join(daemon.stateDir, 'tls/certificate.pem'));
    cert = new X509Certificate(ca);
  });
  after(async () => { await daemon?.stop(); });

  test('is made on first start, verifies for 127.0.0.1, and its fingerprint is in the journal and at setup', async () => {
    assert.match(daemon.url, /^https:/);
    assert.match(cert.subjectAltName, /IP Address:127\.0\.0\.1/);
    assert.match(daemon.log(), new RegExp(`fingerprint ${cert.fingerprint256}`));
    const setup = await call(`${daemon.url}/api/v1/setup`, { ca });
    assert.equal(setup.status, 200);
    assert.equal(JSON.parse(setup.body).tls_fingerprint, cert.fingerprint256);
    const state = await call(`${daemon.url}/api/v1/state`, { ca, headers: authHeaders(daemon.url) });
    assert.equal(state.status, 200);
    // Without trusting it, a client refuses the connection.
    await assert.rejects(call(`${daemon.url}/api/v1/health`), /self[- ]signed/);
  });

  test('plain HTTP on the redirect port only redirects to HTTPS', async () => {
    const res = await call(`http://127.0.0.1:${redirectPort}/api/v1/state?x=1`, { headers: authHeaders(daemon.url) });
    assert.equal(res.status, 308);
    assert.equal(res.headers.location, `https://127.0.0.1:${daemon.port}/api/v1/state?x=1`);
  });

  test('session cookies are Secure; the stream works over WSS', async () => {
    await call(`${daemon.url}/api/v1/users`, {
      method: 'POST', ca, headers: { ...authHeaders(daemon.url), 'Content-Type': 'application/json' },
      body: JSON.stringify({ ...consoleUser, role: 'admin' }),
    });
    const login = await call(`${daemon.url}/api/v1/session`, {
      method: 'POST', ca, headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(consoleUser),
    });
    assert.equal(login.status, 200);
    assert.match(login.headers['set-cookie'][0], /; Secure/);
    const ws = new WebSocket(`${daemon.url.replace('https', 'wss')}/api/v1/stream`, { ca, headers: authHeaders(daemon.url) });
    const first = await new Promise((resolve, reject) => {
      ws.once('message', (d) => resolve(JSON.parse(String(d))));
      ws.once('error', reject);
    });
    ws.close();
    assert.equal(first.topic, 'state');
  });

  test('the console works in Chromium, which trusts the certificate by its key', async () => {
    const spki = createHash('sha256').update(cert.publicKey.export({ type: 'spki', format: 'der' })).digest('base64');
    const browser = await launchBrowser([`--ignore-certificate-errors-spki-list=${spki}`]);
    try {
      const page = await browser.newPage();
      const errors = [];
      page.on('pageerror', (e) => errors.push(e.message));
      await gotoConsole(page, daemon.url, consoleUser);  // made over HTTPS above
      await page.getByTestId('mode').filter({ hasText: 'idle' }).waitFor({ timeout: 10000 });
      assert.deepEqual(errors, []);
    } finally {
      await browser.close();
    }
  });

  test('is kept across restarts', async () => {
    const again = await startDaemon({ stateDir: daemon.stateDir, config: config({ enabled: true }) });
    try {
      const kept = new X509Certificate(readFileSync(join(daemon.stateDir, 'tls/certificate.pem')));
      assert.equal(kept.fingerprint256, cert.fingerprint256);
      assert.doesNotMatch(again.log(), /made now/);
    } finally {
      await again.stop();
    }
  });
});

describe('a configured certificate', () => {
  test('is used, and a broken one stops start-up naming the key', async () => {
    const mine = makeCertificate(dir, 'configured');
    const daemon = await startDaemon({ config: config({ enabled: true, certificate: mine.certFile, key: mine.keyFile }) });
    try {
      const health = await call(`${daemon.url}/api/v1/health`, { ca: mine.cert });
      assert.equal(health.status, 200);
      assert.match(daemon.log(), new RegExp(new X509Certificate(mine.cert).fingerprint256));
    } finally {
      await daemon.stop();
    }
    const file = join(dir, 'broken.yaml');
    const { writeFileSync } = await import('node:fs');
    writeFileSync(file, config({ enabled: true, certificate: mine.keyFile, key: mine.keyFile }));
    const res = await runCorridord(['--config', file, '--port', '0', '--state-dir', join(dir, 'broken-state')]);
    assert.equal(res.code, 1);
    assert.match(res.stderr, /server\.tls\.certificate: .*configured\.key/);
    writeFileSync(file, config({ enabled: true, certificate: mine.certFile }));
    const half = await runCorridord(['--config', file, '--port', '0', '--state-dir', join(dir, 'broken-state')]);
    assert.match(half.stderr, /server\.tls: give both certificate and key/);
  });
});
