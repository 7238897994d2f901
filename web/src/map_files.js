// Saving, loading and downloading the map. Saving and loading go over the WebSocket (the server answers
// with ack or error); the list of saved maps is a REST call with the token as a Bearer credential;
// downloads are plain links, since anyone may watch.
import { authHeaders } from './token.js';

export const NAME_PATTERN = /^[A-Za-z0-9_-][A-Za-z0-9._-]{0,63}$/; // ws-client/save_map.schema.json

export function defaultMapName(date = new Date()) {
  const pad = (n) => String(n).padStart(2, '0');
  return `map-${date.getFullYear()}${pad(date.getMonth() + 1)}${pad(date.getDate())}-${pad(date.getHours())}${pad(date.getMinutes())}.strata`;
}

/** The saved maps, newest first; throws { code, message } as the server reported it. */
export async function listMaps() {
  const response = await fetch('./api/v1/maps', { headers: authHeaders() });
  const body = await response.json().catch(() => null);
  if (!response.ok) {
    throw body?.error ?? { code: 'internal', message: `HTTP ${response.status}` };
  }
  return body.maps.sort((a, b) => b.modified - a.modified);
}

/** Whether the server takes this token (a 401 says it does not; anything else says nothing about it). */
export async function tokenRefused(token) {
  try {
    const response = await fetch('./api/v1/maps', { headers: authHeaders(token) });
    return response.status === 401;
  } catch {
    return false;
  }
}

export function downloadUrl(format) {
  return `./api/v1/map?format=${encodeURIComponent(format)}`;
}

/** The drivable map for ROS map_server: the YAML and the image it names, of one map version. The map
 * changes with every scan, so the image is asked for by the version the YAML came with; when the map has
 * moved on in between (410 Gone), the pair is fetched again. Throws { code, message } as the server
 * reported it. */
export async function fetchRosMap(attempts = 5) {
  const failure = async (response) => (await response.json().catch(() => null))?.error ?? { code: 'internal', message: `HTTP ${response.status}` };
  for (let attempt = 0; attempt < attempts; attempt += 1) {
    const yaml = await fetch(downloadUrl('yaml'));
    if (!yaml.ok) throw await failure(yaml);
    const version = yaml.headers.get('X-Strata-Version');
    const pgm = await fetch(`${downloadUrl('pgm')}&version=${encodeURIComponent(version)}`);
    if (pgm.ok) return { version, yaml: await yaml.blob(), pgm: await pgm.blob() };
    if (pgm.status !== 410) throw await failure(pgm);
  }
  throw { code: 'unavailable', message: `the map changed ${attempts} times while its image was fetched: try again` };
}
