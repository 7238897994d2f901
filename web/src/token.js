// The operator token: entered once, kept for as long as the page (tab) is open. sessionStorage, not
// localStorage, so it does not outlive the session on a shared touch screen. Never put in a URL.
const KEY = 'strata.operatorToken';
const VALID = /^[A-Za-z0-9_-]{16,128}$/; // proto/PROTOCOL.md: 16-128 characters of A-Z a-z 0-9 - _

export function isValidToken(token) {
  return VALID.test(token);
}

export function loadToken() {
  const token = sessionStorage.getItem(KEY);
  return token && isValidToken(token) ? token : null;
}

export function storeToken(token) {
  if (token) sessionStorage.setItem(KEY, token);
  else sessionStorage.removeItem(KEY);
}

/** Headers for a REST call: the token as a Bearer credential, when there is one. */
export function authHeaders(token = loadToken()) {
  return token ? { Authorization: `Bearer ${token}` } : {};
}
