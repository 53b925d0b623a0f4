// One bidirectional session (IkSession, DeformSession) over a WebSocket on
// its REST path, e.g. ws://host/v1/skeletons/walk:ikSession. Each request is
// a JSON text frame and gets one JSON answer, in order. A failed session
// sends its status ({code, message, details}) and closes with 4000 + code:
// the requests waiting then reject with an Error carrying that message and
// `code`. With a bearer token, browsers (which cannot set Authorization on a
// WebSocket) send it as the subprotocol "bearer.<token>".
const MAX_LOG = 512;  // requests and round trips kept for inspection

export class SessionSocket {
  // Resolves once the connection is open.
  static open(path, { token } = {}) {
    const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
    const socket = new WebSocket(`${scheme}://${location.host}${path}`, token ? [`bearer.${token}`] : []);
    return new Promise((resolve, reject) => {
      socket.onopen = () => resolve(new SessionSocket(socket));
      socket.onerror = () => reject(new Error(`could not open a session at ${path}`));
    });
  }

  constructor(socket) {
    this.socket = socket;
    this.waiting = [];      // { resolve, reject, sent } per request, in order
    this.status = null;     // the final status frame, once received
    this.sent = [];         // the requests (JSON text), the latest MAX_LOG
    this.roundTrips = [];   // ms from sending a request to its answer arriving
    socket.onmessage = (event) => this.onMessage(event.data);
    socket.onclose = (event) => this.onClose(event);
    socket.onerror = null;
  }

  get open() {
    return this.socket.readyState === WebSocket.OPEN;
  }

  // Sends one request message; resolves with its answer.
  request(message) {
    if (!this.open) return Promise.reject(this.failure() ?? new Error('the session is closed'));
    const text = JSON.stringify(message);
    return new Promise((resolve, reject) => {
      this.waiting.push({ resolve, reject, sent: performance.now() });
      this.socket.send(text);
      keep(this.sent, text);
    });
  }

  // Ends the session (the server answers what is left, then closes).
  close() {
    if (this.socket.readyState <= WebSocket.OPEN) this.socket.close(1000);
  }

  onMessage(data) {
    const arrived = performance.now();
    const message = JSON.parse(data);
    if (typeof message.code === 'number' && Array.isArray(message.details) && !('positions' in message)) {
      this.status = message;  // the session failed: the close follows
      return;
    }
    const next = this.waiting.shift();
    if (!next) return;
    keep(this.roundTrips, arrived - next.sent);
    next.resolve(message);
  }

  failure() {
    if (!this.status) return null;
    const error = new Error(this.status.message);
    error.code = this.status.code;
    return error;
  }

  onClose(event) {
    const error = this.failure() ??
      new Error(event.code === 1000 ? 'the session ended' : `the session closed (${event.code} ${event.reason})`);
    for (const w of this.waiting.splice(0)) w.reject(error);
  }
}

function keep(list, value) {
  list.push(value);
  if (list.length > MAX_LOG) list.splice(0, list.length - MAX_LOG);
}
