// The WebSocket link to the strata server: subprotocol strata.v1 (proto/PROTOCOL.md), JSON messages,
// automatic reconnect with capped exponential backoff.

export const SUBPROTOCOL = 'strata.v1';

export function websocketUrl(location = window.location) {
  const scheme = location.protocol === 'https:' ? 'wss:' : 'ws:';
  return `${scheme}//${location.host}/ws`;
}

export class Connection {
  constructor(url, { onMessage, onState }) {
    this.url = url;
    this.onMessage = onMessage;
    this.onState = onState;
    this.retryDelayMs = 500;
    this.socket = null;
  }

  open() {
    this.onState('connecting');
    const socket = new WebSocket(this.url, [SUBPROTOCOL]);
    this.socket = socket;
    socket.addEventListener('open', () => {
      this.retryDelayMs = 500;
      this.onState('connected');
    });
    socket.addEventListener('message', (event) => {
      if (typeof event.data !== 'string') return; // binary frames arrive with later protocol features
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
      if (this.socket !== socket) return;
      this.onState('disconnected');
      setTimeout(() => this.open(), this.retryDelayMs);
      this.retryDelayMs = Math.min(this.retryDelayMs * 2, 8000);
    });
  }

  send(message) {
    if (this.socket?.readyState === WebSocket.OPEN) this.socket.send(JSON.stringify(message));
  }
}
