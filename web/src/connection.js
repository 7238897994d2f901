// The WebSocket link to the strata server: subprotocol strata.v1 (proto/PROTOCOL.md), JSON text messages
// and binary frames, automatic reconnect with capped exponential backoff. A browser cannot set headers on
// a WebSocket, so the operator token travels as a second subprotocol, strata.token.<token>.

export const SUBPROTOCOL = 'strata.v1';

export function websocketUrl(location = window.location) {
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
  return `${scheme}//${location.host}/ws`;
}

export class Connection {
  /**
   * onMessage(json), onBinary(ArrayBuffer), onState('connecting' | 'connected' | 'disconnected'),
   * onRefused(): the socket closed before it ever opened (server down, or a wrong token refused with 401).
   */
  constructor(url, { onMessage, onBinary = () => {}, onState, onRefused = () => {} }) {
    this.url = url;
    this.onMessage = onMessage;
    this.onBinary = onBinary;
    this.onState = onState;
    this.onRefused = onRefused;
    this.retryDelayMs = 500;
    this.socket = null;
    this.token = null;
    this.retryTimer = null;
  }

  open() {
    clearTimeout(this.retryTimer);
    this.onState('connecting');
    const protocols = this.token ? [SUBPROTOCOL, `strata.token.${this.token}`] : [SUBPROTOCOL];
    const socket = new WebSocket(this.url, protocols);
    socket.binaryType = 'arraybuffer';
    this.socket = socket;
    let opened = false;
    socket.addEventListener('open', () => {
      if (this.socket !== socket) return;
      opened = true;
      this.retryDelayMs = 500;
      this.onState('connected');
    });
    socket.addEventListener('message', (event) => {
      if (this.socket !== socket) return;
      if (typeof event.data !== 'string') {
        this.onBinary(event.data);
        return;
      }
      let message;
      try {
        message = JSON.parse(event.data);
      } catch {
        console.warn('strata: ignoring a message that is not JSON');
        return;
      }
      this.onMessage(message);
    });
    socket.addEventListener('close', () => {
      if (this.socket !== socket) return; // replaced by a newer socket on purpose (token change)
      this.onState('disconnected');
      if (!opened) this.onRefused();
      this.retryTimer = setTimeout(() => this.open(), this.retryDelayMs);
      this.retryDelayMs = Math.min(this.retryDelayMs * 2, 8000);
    });
  }

  /** Reconnect with another operator token (null: as a viewer); the server decides the role at connect. */
  useToken(token) {
    this.token = token;
    const old = this.socket;
    this.socket = null;
    old?.close();
    this.retryDelayMs = 500;
    this.open();
  }

  get isOpen() {
    return this.socket?.readyState === WebSocket.OPEN;
  }

  send(message) {
    if (!this.isOpen) return false;
    this.socket.send(JSON.stringify(message));
    return true;
  }
}
