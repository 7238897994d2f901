// The REST API against its document (issue 59 item 13): proto/openapi.yaml must be valid OpenAPI 3.1 (by
// @apidevtools/swagger-parser, not by us), and the real server must answer every documented request with a
// documented status and a body that matches the documented schema (by ajv), as a contract-testing proxy
// would check it. Also across all operations: a method not documented gets 405 with an Allow header naming
// exactly the documented ones; a body that is not JSON gets 400 `bad_json`; an operator endpoint without
// the token gets 401.
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import SwaggerParser from '@apidevtools/swagger-parser';
import Ajv from 'ajv';
import { startServer } from '../browser/server.mjs';

const document = new URL('../../proto/openapi.yaml', import.meta.url).pathname;
const token = 'openapi-contract-test-operator-token';
const methods = ['get', 'post', 'put', 'delete', 'patch'];
let server;
let api;
let maps;
const ajv = new Ajv({ strict: false, allErrors: true });

before(async () => {
  maps = mkdtempSync(join(tmpdir(), 'strata-openapi-maps-'));
  server = await startServer(process.env.STRATA_BINARY, [
    '--time-scale', '5', '--operator-token', token, '--maps-dir', maps,
  ]);
  api = await SwaggerParser.dereference(document);
  // A map to download, save and load.
  for (let i = 0; ; i++) {
    const status = await (await fetch(`${server.url}/api/v1/status`)).json();
    if (status.map?.tiles > 0 && status.pose !== null) break;
    if (i === 600) throw new Error(`no map after 60 s: ${JSON.stringify(status)}`);
    await new Promise((resolve) => setTimeout(resolve, 100));
  }
});

after(async () => {
  await server?.stop();
  rmSync(maps, { recursive: true, force: true });
});

/// The operation for `path` and `method` in the document, or undefined.
function operation(path, method) {
  return api.paths[path]?.[method];
}

/// Sends the request; checks its status is documented for the operation and its JSON body matches the
/// documented schema. Returns the response and its body text.
async function call(path, method, { target = path, body, operator = false, headers = {} } = {}) {
  const spec = operation(path, method);
  assert.ok(spec, `${method.toUpperCase()} ${path} is not in the document`);
  const response = await fetch(`${server.url}${target}`, {
    method: method.toUpperCase(),
    headers: {
      ...(operator ? { Authorization: `Bearer ${token}` } : {}),
      ...(body !== undefined ? { 'Content-Type': 'application/json' } : {}),
      ...headers,
    },
    body,
  });
  const text = await response.text();
  const where = `${method.toUpperCase()} ${target} -> ${response.status} ${text.slice(0, 300)}`;
  const documented = spec.responses[String(response.status)];
  assert.ok(documented, `undocumented status: ${where}`);
  const type = (response.headers.get('content-type') ?? '').split(';')[0];
  const schema = documented.content?.[type]?.schema;
  if (type === 'application/json') {
    assert.ok(schema, `no schema documented for this JSON answer: ${where}`);
    const validate = ajv.compile(schema);
    assert.ok(validate(JSON.parse(text)), `${where}\n${ajv.errorsText(validate.errors)}`);
  } else if (response.status !== 304 && text.length > 0) {
    assert.ok(documented.content?.[type], `undocumented content type ${type}: ${where}`);
  }
  return { response, text };
}

test('the document is valid OpenAPI 3.1', async () => {
  const valid = await SwaggerParser.validate(document);
  assert.match(valid.openapi, /^3\.1\./);
});

test('every documented operation answers as documented', async () => {
  const ok = async (path, method, options) => {
    const { response, text } = await call(path, method, options);
    assert.ok(response.status < 400, `${method} ${path}: ${response.status} ${text.slice(0, 200)}`);
    return { response, text };
  };
  await ok('/healthz', 'get');
  await ok('/api/v1/info', 'get');
  await ok('/api/v1/pose', 'get');
  await ok('/api/v1/status', 'get');
  await ok('/api/v1/sim/world', 'get');
  await ok('/metrics', 'get');
  await ok('/api/v1/path', 'get');
  await ok('/api/v1/imu-calibration', 'get');
  for (const format of ['strata', 'ply', 'pgm', 'yaml', 'mcap'])
    await ok('/api/v1/map', 'get', { target: `/api/v1/map?format=${format}` });
  await ok('/api/v1/map', 'get', { target: '/api/v1/map?format=mcap&compression=none' });
  await call('/api/v1/map', 'get', { target: '/api/v1/map?format=obj' });
  await call('/api/v1/map', 'get', { target: '/api/v1/map?format=pgm&compression=zstd' });
  await call('/api/v1/map', 'get', { target: '/api/v1/map?format=pgm&version=1' });
  const { response: image } = await ok('/api/v1/occupancy', 'get');
  await call('/api/v1/occupancy', 'get', { headers: { 'If-None-Match': image.headers.get('etag') } });
  const index = JSON.parse((await ok('/api/v1/tiles', 'get')).text);
  const first = index.tiles[0];
  await ok('/api/v1/tiles/{x}/{y}', 'get', { target: `/api/v1/tiles/${first.x}/${first.y}` });
  await call('/api/v1/tiles/{x}/{y}', 'get', { target: '/api/v1/tiles/100000/100000' });

  await ok('/api/v1/goal', 'get');
  const goal = JSON.parse((await ok('/api/v1/goal', 'post', { body: '{"x":1,"y":1}', operator: true })).text);
  assert.ok(goal.id > 0, JSON.stringify(goal));
  await call('/api/v1/goal', 'post', { body: '{"x":"far"}', operator: true });
  await ok('/api/v1/goal', 'delete', { operator: true });
  await call('/api/v1/pose/estimate', 'post', { body: '{"x":0,"y":0,"yaw":0}', operator: true });

  await ok('/api/v1/maps', 'post', { body: '{"name":"contract.strata"}', operator: true });
  await call('/api/v1/maps', 'post', { body: '{"name":"../escape"}', operator: true });
  const listed = JSON.parse((await ok('/api/v1/maps', 'get')).text);
  assert.ok(listed.maps.some((map) => map.name === 'contract.strata'), JSON.stringify(listed));
  await ok('/api/v1/maps/{name}/load', 'post', {
    target: '/api/v1/maps/contract.strata/load', body: '{"mode":"localize"}', operator: true,
  });
  await call('/api/v1/maps/{name}/load', 'post', {
    target: '/api/v1/maps/absent.strata/load', body: '{}', operator: true,
  });
  await call('/api/v1/imu-calibration', 'delete', { operator: true });

  // The map server: the save above made version 1 of contract.strata.
  const versions = JSON.parse((await ok('/api/v1/map-versions', 'get')).text).versions;
  const saved = versions.find((v) => v.name === 'contract.strata');
  assert.ok(saved, JSON.stringify(versions));
  const file = '/api/v1/maps/{name}/versions/{version}';
  const { response: whole } = await ok(file, 'get', { target: saved.url });
  assert.equal(whole.headers.get('etag'), `"${saved.sha256}"`);
  await ok(file, 'get', { target: saved.url, headers: { 'If-None-Match': whole.headers.get('etag') } });
  await ok(file, 'get', { target: saved.url, headers: { Range: 'bytes=0-9' } });
  await call(file, 'get', { target: saved.url, headers: { Range: `bytes=${saved.bytes}-` } });
  await call(file, 'get', { target: '/api/v1/maps/contract.strata/versions/999' });
});

test('operator endpoints refuse a request without the token with 401', async () => {
  for (const [path, spec] of Object.entries(api.paths)) {
    for (const method of methods) {
      if (!spec[method]?.security?.length) continue;
      const target = path.replace('{name}', 'contract.strata');
      const { response } = await call(path, method, { target, body: method === 'post' ? '{}' : undefined });
      assert.equal(response.status, 401, `${method} ${target}`);
    }
  }
});

test('a body that is not JSON is refused with 400 bad_json everywhere', async () => {
  for (const [path, spec] of Object.entries(api.paths)) {
    if (!spec.post?.requestBody) continue;
    const target = path.replace('{name}', 'contract.strata');
    const { response, text } = await call(path, 'post', { target, body: '{"x":', operator: true });
    assert.equal(response.status, 400, `${target}: ${text}`);
    assert.equal(JSON.parse(text).error.code, 'bad_json', `${target}: ${text}`);
  }
});

test('a method not documented gets 405 and an Allow header naming the documented ones', async () => {
  for (const [path, spec] of Object.entries(api.paths)) {
    if (path === '/ws') continue; // the upgrade is a GET; documented for its statuses
    const target = path.replace('{x}', '0').replace('{y}', '0').replace('{name}', 'contract.strata').replace('{version}', '1');
    const documented = methods.filter((method) => spec[method]);
    const other = methods.find((method) => !documented.includes(method));
    const response = await fetch(`${server.url}${target}`, {
      method: other.toUpperCase(),
      headers: { Authorization: `Bearer ${token}` },
    });
    const text = await response.text();
    assert.equal(response.status, 405, `${other} ${target}: ${text}`);
    const allowed = (response.headers.get('allow') ?? '').split(',').map((m) => m.trim().toLowerCase());
    for (const method of documented)
      assert.ok(allowed.includes(method), `${target}: Allow "${response.headers.get('allow')}" lacks ${method}`);
    for (const method of allowed.filter((m) => m !== 'head'))
      assert.ok(documented.includes(method), `${target}: Allow names ${method}, not documented`);
    assert.equal(JSON.parse(text).error.code, 'method_not_allowed', text);
  }
});
