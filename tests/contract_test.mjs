// The contract suite (tests/contract/run.mjs) against corridord with the simulator, through its command line as an
// integrator would run it, writes included; and against a server that breaks its own contract, which it must catch.
import assert from 'node:assert/strict';
import { execFile } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { createServer } from 'node:http';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { promisify } from 'node:util';
import { after, before, describe, test } from 'node:test';

import { authHeaders, mintToken, sourceDir, startDaemon, writeRoom } from './daemon.mjs';
import { runContract } from './contract/run.mjs';

const run = promisify(execFile);

describe('the API contract', () => {
  let daemon;
  let dir;
  before(async () => {
    dir = mkdtempSync(join(tmpdir(), 'corridor-contract-'));
    daemon = await startDaemon({ config: `
sim:
  world: "${writeRoom(dir, 4, 3)}"
  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 0}
  camera: {width: 160, height: 120}
  dock: {enabled: true, x_m: 3.2, y_m: 1.5, yaw_deg: 0}
` });
  });
  after(async () => {
    await daemon?.stop();
    rmSync(dir, { recursive: true, force: true });
  });

  test('every route of the OpenAPI document keeps it, valid and invalid requests alike', async () => {
    const token = authHeaders(daemon.url).Authorization.replace('Bearer ', '');
    const { stdout } = await run('node', [join(sourceDir, 'tests/contract/run.mjs'), '--url', daemon.url, '--token', token,
      '--writes'], { maxBuffer: 16 * 1024 * 1024 }).catch((e) => { throw new Error(`${e.message}\n${e.stdout}`); });
    const summary = /(\d+) checks, (\d+) failed/.exec(stdout);
    assert.ok(summary, stdout);
    assert.equal(Number(summary[2]), 0, stdout);
    assert.ok(Number(summary[1]) > 300, `only ${summary[1]} checks`);
  });

  test('a viewer\'s writes are refused as the document says, and change nothing', async () => {
    const viewer = mintToken(daemon.stateDir, 'viewer', 'contract-viewer');
    const { checks, failures } = await runContract({ url: daemon.url, token: viewer, writes: true });
    assert.deepEqual(failures, []);
    assert.ok(checks > 300);
  });
});

test('a server that breaks its contract is caught', async () => {
  const doc = {
    openapi: '3.1.0', info: { title: 'broken', version: '0' },
    components: {
      schemas: { Thing: { type: 'object', required: ['n'], additionalProperties: false,
        properties: { n: { type: 'integer', minimum: 1, maximum: 5 } } } },
      responses: { Problem: { description: 'refused', content: { 'application/problem+json': { schema: { type: 'object' } } } } },
    },
    paths: {
      '/api/v1/things': {
        post: {
          'x-corridor-access': 'admin',
          requestBody: { required: true, content: { 'application/json': { schema: { $ref: '#/components/schemas/Thing' } } } },
          responses: { 201: { description: 'made', content: { 'application/json': { schema: { $ref: '#/components/schemas/Thing' } } } },
            400: { $ref: '#/components/responses/Problem' }, 413: { $ref: '#/components/responses/Problem' },
            415: { $ref: '#/components/responses/Problem' } },
        },
      },
    },
  };
  let things = 0;
  // Takes anything, from a viewer too, and answers with what the schema forbids.
  const server = createServer((req, res) => {
    if (req.url === '/api/v1/openapi.json') return res.end(JSON.stringify(doc));
    if (req.url === '/api/v1/session') return res.end(JSON.stringify({ name: 'v', role: 'viewer', kind: 'token' }));
    req.resume();
    req.on('end', () => {
      if (req.url === '/api/v1/things') ++things;
      res.writeHead(req.url === '/api/v1/things' ? 201 : 200, { 'Content-Type': 'application/json' });
      res.end(JSON.stringify({ n: 'many', count: things }));
    });
  });
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  try {
    const { failures } = await runContract({ url: `http://127.0.0.1:${server.address().port}`, writes: true });
    const text = failures.join('\n');
    assert.match(text, /POST \/api\/v1\/things \(valid \{"n":1\}\): 201 body does not match/);
    assert.match(text, /\('n' missing\): expected a 4xx refusal, got 201/);
    assert.match(text, /\('n' above its maximum\): expected a 4xx refusal/);
    assert.match(text, /\(the wrong content type\): expected a 4xx refusal/);
    assert.match(text, /an invalid request changed the robot's data|expected a 4xx/);
    assert.match(text, /\(valid \{"n":1\}\): a viewer was not refused \(201\), the document says admin/);
  } finally {
    server.close();
  }
});
