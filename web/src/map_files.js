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
