#!/usr/bin/env node
// The API contract, checked against a running corridord: every route of its OpenAPI document (/api/v1/openapi.json)
// gets requests made from the document itself.
//   - valid: built from the request's schema (required fields, values within their bounds); the answer's status
//     must be documented for the route and its body must validate against the documented schema;
//   - invalid: malformed JSON, the wrong content type, an oversized body, each required field missing, each field of
//     the wrong type, a field the schema does not allow, numbers out of range; each must get a documented 4xx
//     answer with a problem+json body, and change nothing (the robot's places, zones, missions, webhooks, users,
//     tokens, map and mission in progress read the same before and after);
//   - access: with credentials, the gate refuses (403) exactly the routes whose x-corridor-access is above the
//     caller's role.
// Writes can move a real robot: without --writes only reads are sent valid (invalid writes are refused before they
// act). Use --writes against a simulator or a robot standing where it may drive.
//
//   node tests/contract/run.mjs --url https://robot:8443 [--token TOKEN] [--writes] [--insecure] [--only REGEX]
//
// Node's own fetch; Ajv from the console's npm packages (web/node_modules). Exits 1 when a check fails.
import { createRequire } from 'node:module';
import { connect as netConnect } from 'node:net';
import { connect as tlsConnect } from 'node:tls';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

const here = dirname(fileURLToPath(import.meta.url));
const require = createRequire(join(here, '../../web/package.json'));
const kOversizedBytes = 5 * 1024 * 1024;  // beyond server.max_body_bytes unless it was raised past 4 MiB
// Routes the suite does not call: the WebSocket (its own protocol) and those that end the caller's credentials.
const kSkipped = new Set(['GET /api/v1/stream', 'DELETE /api/v1/session']);

// A value that satisfies `schema` (its required fields only), resolving references in `doc`.
export function example(schema, doc, depth = 0) {
  schema = resolve(schema, doc);
  if (depth > 8) return null;
  if (schema.const !== undefined) return schema.const;
  if (schema.enum) return schema.enum.find((v) => v !== '') ?? schema.enum[0];
  if (schema.oneOf || schema.anyOf) return example((schema.oneOf ?? schema.anyOf)[0], doc, depth + 1);
  if (schema.allOf) return Object.assign({}, ...schema.allOf.map((s) => example(s, doc, depth + 1)));
  const type = Array.isArray(schema.type) ? schema.type.find((t) => t !== 'null') : schema.type;
  switch (type ?? (schema.properties ? 'object' : undefined)) {
    case 'object': {
      const out = {};
      for (const key of schema.required ?? []) out[key] = example(schema.properties?.[key] ?? {}, doc, depth + 1);
      return out;
    }
    case 'array': {
      const n = Math.max(schema.minItems ?? 1, 1);
      return Array.from({ length: n }, () => example(schema.items ?? {}, doc, depth + 1));
    }
    case 'integer':
    case 'number': {
      let v = schema.minimum ?? (schema.exclusiveMinimum !== undefined ? schema.exclusiveMinimum + 1 : 1);
      if (schema.maximum !== undefined) v = Math.min(v, schema.maximum);
      return type === 'integer' ? Math.ceil(v) : v;
    }
    case 'boolean': return false;
    case 'string': return 'contract'.padEnd(schema.minLength ?? 0, 'x').slice(0, schema.maxLength ?? 64);
    default: return null;
  }
}

export function resolve(schema, doc) {
  while (schema?.$ref) {
    schema = schema.$ref.replace(/^#\//, '').split('/').reduce((node, key) => node[key], doc);
  }
  return schema ?? {};
}

// Invalid variants of a valid JSON object body for `schema`: [what, body] pairs.
export function invalidBodies(schema, valid, doc) {
  schema = resolve(schema, doc);
  if (schema.type !== 'object' && !schema.properties) return [['not an object', JSON.stringify([valid])]];
  const out = [['an array instead of an object', JSON.stringify([valid])]];
  for (const key of schema.required ?? []) {
    const body = { ...valid };
    delete body[key];
    out.push([`'${key}' missing`, JSON.stringify(body)]);
  }
  for (const [key, property] of Object.entries(schema.properties ?? {})) {
    const p = resolve(property, doc);
    const types = [].concat(p.type ?? []);
    if (p.oneOf || p.anyOf || types.length === 0) continue;
    const wrong = types.includes('string') ? 12345 : types.includes('object') ? 'text'
      : types.includes('array') ? { not: 'an array' } : 'text';
    if (types.includes('null') && wrong === null) continue;
    out.push([`'${key}' of the wrong type`, JSON.stringify({ ...valid, [key]: wrong })]);
    if (p.minimum !== undefined) out.push([`'${key}' below its minimum`, JSON.stringify({ ...valid, [key]: p.minimum - 1 })]);
    if (p.maximum !== undefined) out.push([`'${key}' above its maximum`, JSON.stringify({ ...valid, [key]: p.maximum + 1 })]);
    if (p.enum && types.includes('string')) out.push([`'${key}' not one of its values`, JSON.stringify({ ...valid, [key]: 'no-such-value' })]);
  }
  if (schema.additionalProperties === false) {
    out.push(['a field the schema does not allow', JSON.stringify({ ...valid, contract_extra_field: 1 })]);
  }
  return out;
}

function parseArgs(argv) {
  const args = { url: null, token: null, writes: false, insecure: false, only: null };
  for (let i = 0; i < argv.length; ++i) {
    const a = argv[i];
    if (a === '--url') args.url = argv[++i];
    else if (a === '--token') args.token = argv[++i];
    else if (a === '--writes') args.writes = true;
    else if (a === '--insecure') args.insecure = true;
    else if (a === '--only') args.only = new RegExp(argv[++i]);
    else if (a === '--help' || a === '-h') args.help = true;
    else throw new Error(`unknown argument '${a}' (see --help)`);
  }
  return args;
}

// Runs the suite; resolves to { checks, failures: [strings] }. `log` receives one line per failure.
export async function runContract({ url, token = null, writes = false, only = null, log = () => {} }) {
  const base = url.replace(/\/$/, '');
  const headers = token ? { Authorization: `Bearer ${token}` } : {};
  const call = async (method, path, body, contentType = 'application/json') => {
    const init = { method, headers: { ...headers } };
    if (body !== undefined) {
      init.body = body;
      init.headers['Content-Type'] = contentType;
    }
    const res = await fetch(`${base}${path}`, init);
    const text = await res.text();
    let json = null;
    try { json = text ? JSON.parse(text) : null; } catch { json = undefined; }
    return { status: res.status, type: res.headers.get('content-type') ?? '', json, text };
  };
  // An oversized body over a socket of its own: the server answers 413 and closes while the body is still being sent,
  // which HTTP clients report as a failed write; the answer is what counts.
  const oversized = (method, path) => new Promise((resolveCall, reject) => {
    const target = new URL(`${base}${path}`);
    const port = Number(target.port || (target.protocol === 'https:' ? 443 : 80));
    const socket = target.protocol === 'https:'
      ? tlsConnect({ host: target.hostname, port, servername: target.hostname,
        rejectUnauthorized: process.env.NODE_TLS_REJECT_UNAUTHORIZED !== '0' })
      : netConnect({ host: target.hostname, port });
    const head = [`${method} ${target.pathname}${target.search} HTTP/1.1`, `Host: ${target.host}`,
      'Content-Type: application/json', `Content-Length: ${kOversizedBytes}`, 'Connection: close',
      ...Object.entries(headers).map(([k, v]) => `${k}: ${v}`), '', ''].join('\r\n');
    const chunks = [];
    let answered = false;
    socket.on('data', (d) => { chunks.push(d); answered = true; });
    socket.on('error', (e) => { if (!['EPIPE', 'ECONNRESET'].includes(e.code)) reject(e); });
    socket.on('close', () => {
      const text = Buffer.concat(chunks).toString('utf8');
      const [headText, ...rest] = text.split('\r\n\r\n');
      const status = Number(/^HTTP\/1\.[01] (\d{3})/.exec(headText)?.[1] ?? 0);
      const type = /\r\ncontent-type:\s*([^\r\n]+)/i.exec(headText)?.[1] ?? '';
      const body = rest.join('\r\n\r\n');
      let json;
      try { json = JSON.parse(body); } catch { json = undefined; }
      resolveCall({ status, type, json, text: body || text });
    });
    socket.write(head);
    const chunk = Buffer.alloc(64 * 1024, 0x20);
    let sent = 0;
    const pump = () => {
      while (sent < kOversizedBytes && !answered && !socket.destroyed) {
        sent += chunk.length;
        if (!socket.write(chunk)) { socket.once('drain', pump); return; }
      }
    };
    pump();
  });
  const docResponse = await call('GET', '/api/v1/openapi.json');
  if (docResponse.status !== 200 || !docResponse.json) throw new Error(`${base}/api/v1/openapi.json: ${docResponse.status}`);
  const doc = docResponse.json;
  const Ajv2020 = require('ajv/dist/2020').default;
  const ajv = new Ajv2020({ strict: false, allErrors: true, validateFormats: false });
  ajv.addSchema({ ...doc, $id: 'contract' });
  // The validator of the schema at `pointer` (a JSON pointer into the document): references inside it resolve
  // against the whole document.
  const validator = (pointer) => ajv.getSchema(`contract#${pointer}`);
  const escape = (key) => encodeURIComponent(key.replace(/~/g, '~0').replace(/\//g, '~1'));

  // The caller's role (a token or a session; none without credentials), and whether it may call `op` as the
  // operation's x-corridor-access says: the gate must refuse it (403 "forbidden") exactly when it may not.
  const kRanks = ['anyone', 'screen', 'viewer', 'operator', 'admin'];
  const session = await call('GET', '/api/v1/session');
  const role = session.status === 200 ? session.json.role : undefined;
  const checkAccess = (label, op, res) => {
    if (!role) return;
    ++checks;
    const needed = op['x-corridor-access'];
    if (!kRanks.includes(needed)) {
      fail(`${label}: x-corridor-access is '${needed}'`);
      return;
    }
    const refused = res.status === 403 && res.json?.code === 'forbidden';
    const allowed = kRanks.indexOf(role) >= kRanks.indexOf(needed);
    if (refused === allowed) {
      fail(`${label}: a ${role} was ${refused ? '' : 'not '}refused (${res.status}), the document says ${needed}`);
    }
  };

  // What an invalid request must not change.
  const fingerprint = async () => {
    const parts = [];
    for (const path of ['/api/v1/places', '/api/v1/zones', '/api/v1/missions', '/api/v1/webhooks', '/api/v1/users',
      '/api/v1/tokens', '/api/v1/maps']) {
      const r = await call('GET', path);
      parts.push(r.status === 200 ? JSON.stringify(r.json, (k, v) => (['last_used', 'eta_s', 'progress',
        'remaining_on_leg_m', 'path', 'policy', 'docking', 'status', 'current_waypoint', 'error'].includes(k) ? undefined : v)) : r.status);
    }
    const state = (await call('GET', '/api/v1/state')).json;
    parts.push(state?.mission?.id ?? null, state?.map?.revision ?? null);
    return parts.join('\n');
  };

  const failures = [];
  let checks = 0;
  const fail = (what) => { failures.push(what); log(`FAIL ${what}`); };
  const expect = (label, op, res, wantProblem) => {
    ++checks;
    const documented = op.responses?.[String(res.status)];
    if (!documented) {
      fail(`${label}: ${res.status} is not documented (${res.text.slice(0, 200)})`);
      return;
    }
    if (wantProblem) {
      if (res.status < 400 || res.status >= 500) fail(`${label}: expected a 4xx refusal, got ${res.status}`);
      if (!res.type.startsWith('application/problem+json')) fail(`${label}: ${res.status} without a problem+json body`);
      return;
    }
    if (res.status >= 500) fail(`${label}: ${res.status} ${res.text.slice(0, 200)}`);
    // Where the answer's schema is: in the route's responses, or in the shared responses they refer to.
    const responsePointer = documented.$ref ? documented.$ref.replace(/^#/, '')
      : `/paths/${escape(op.path)}/${op.method}/responses/${res.status}`;  // (own: only theirs are inline)
    const content = resolve(documented, doc).content ?? {};
    const type = ['application/json', 'application/problem+json'].find((t) => content[t]?.schema);
    if (type && res.json !== undefined && res.json !== null) {
      const validate = validator(`${responsePointer}/content/${escape(type)}/schema`);
      if (!validate(res.json)) fail(`${label}: ${res.status} body does not match: ${ajv.errorsText(validate.errors)}`);
    }
  };

  for (const [pathTemplate, operations] of Object.entries(doc.paths)) {
    for (const [method, op] of Object.entries(operations)) {
      if (!['get', 'post', 'put', 'patch', 'delete'].includes(method)) continue;
      const key = `${method.toUpperCase()} ${pathTemplate}`;
      op.path = pathTemplate;
      op.method = method;
      if (kSkipped.has(key) || (only && !only.test(key))) continue;
      if (process.env.CONTRACT_TRACE) console.error(key);
      // Path parameters name something that does not exist; required query parameters get example values.
      let path = pathTemplate.replace(/\{[^}]+\}/g, 'contract-missing');
      const query = (op.parameters ?? []).filter((p) => p.in === 'query' && p.required)
        .map((p) => `${p.name}=${encodeURIComponent(example(p.schema ?? {}, doc))}`);
      if (query.length) path += `?${query.join('&')}`;
      const jsonBody = op.requestBody?.content?.['application/json']?.schema;
      const valid = jsonBody ? example(jsonBody, doc) : undefined;
      const read = method === 'get';
      if (read || writes) {
        const res = await call(method.toUpperCase(), path, valid === undefined ? undefined : JSON.stringify(valid));
        const label = `${key} (valid${valid === undefined ? '' : ` ${JSON.stringify(valid)}`})`;
        expect(label, op, res, false);
        checkAccess(label, op, res);
      }
      if (!op.requestBody) continue;
      // What a valid write changed may still be on its way to the database: wait until the data holds still.
      let before = await fingerprint();
      for (let i = 0; i < 40; ++i) {
        await new Promise((r) => setTimeout(r, 50));
        const again = await fingerprint();
        if (again === before) break;
        before = again;
      }
      expect(`${key} (an oversized body)`, op, await oversized(method.toUpperCase(), path), true);
      const cases = [['malformed JSON', '{"', 'application/json']];
      if (jsonBody) {
        cases.push(['the wrong content type', JSON.stringify(valid), 'text/plain']);
        for (const [what, body] of invalidBodies(jsonBody, valid, doc)) cases.push([what, body, 'application/json']);
      }
      for (const [what, body, type] of cases) {
        const res = await call(method.toUpperCase(), path, body, type);
        expect(`${key} (${what})`, op, res, true);
        checkAccess(`${key} (${what})`, op, res);
      }
      const after = await fingerprint();
      ++checks;
      if (after !== before) fail(`${key}: an invalid request changed the robot's data`);
    }
  }
  return { checks, failures };
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const args = parseArgs(process.argv.slice(2));
  if (args.help || !args.url) {
    console.log('usage: node tests/contract/run.mjs --url URL [--token TOKEN] [--writes] [--insecure] [--only REGEX]');
    process.exit(args.help ? 0 : 2);
  }
  if (args.insecure) process.env.NODE_TLS_REJECT_UNAUTHORIZED = '0';
  const { checks, failures } = await runContract({ ...args, log: (line) => console.log(line) });
  console.log(`${checks} checks, ${failures.length} failed`);
  process.exit(failures.length ? 1 : 0);
}
