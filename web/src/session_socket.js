// One bidirectional session (IkSession, DeformSession) over a WebSocket on
// its REST path, e.g. ws://host/v1/skeletons/walk:ikSession. Each request is
// a JSON text frame and gets one JSON answer, in order; a request in binary
// (its proto encoding) gets its answer's encoding. A failed session
// sends its status ({code, message, details}) and closes with 4000 + code:
// the requests waiting then reject with an Error carrying that message and
// `code`. With a bearer token, browsers (which cannot set Authorization on a
// WebSocket) send it as the subprotocol "bearer.<token>".
//
// The socket lives in a small dedicated worker, so answers are received (and
// their round trips timed) as they arrive, even while the page's thread is
// busy drawing; the page then handles them in order.
const MAX_LOG = 512;  // requests and round trips kept for inspection

// The worker: owns the WebSocket, stamps each answer with its round trip.
function socketWorker() {
  let socket = null;
  const sentAt = [];  // send times of the requests not yet answered, in order
  self.onmessage = ({ data }) => {
    if (data.open) {
      socket = new WebSocket(data.open, data.protocols);
      socket.binaryType = 'arraybuffer';
      socket.onopen = () => self.postMessage({ opened: true });
      socket.onerror = () => self.postMessage({ failed: true });
      socket.onmessage = (e) => {
        const answer = { answer: e.data, ms: performance.now() - sentAt.shift() };
        self.postMessage(answer, e.data instanceof ArrayBuffer ? [e.data] : []);
      };
      socket.onclose = (e) => self.postMessage({ closed: { code: e.code, reason: e.reason } });
    } else if (data.send !== undefined) {
      sentAt.push(performance.now());
      socket.send(data.send);
    } else if (data.close) {
      socket?.close(1000);
    }
  };
}
let workerUrl = null;

export class SessionSocket {
  // Resolves once the connection is open.
  static open(path, { token } = {}) {
    const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
    workerUrl ??= URL.createObjectURL(new Blob([`(${socketWorker})()`], { type: 'text/javascript' }));
    const worker = new Worker(workerUrl);
    const url = `${scheme}://${location.host}${path}`;
    return new Promise((resolve, reject) => {
      worker.onmessage = ({ data }) => {
        if (data.opened) return resolve(new SessionSocket(worker, url));
        worker.terminate();
        reject(new Error(`could not open a session at ${path}`));
      };
      worker.postMessage({ open: url, protocols: token ? [`bearer.${token}`] : [] });
    });
  }

  constructor(worker, url) {
    this.worker = worker;
    this.url = url;
    this.isOpen = true;
    this.waiting = [];         // { resolve, reject } per request, in order
    this.status = null;        // the final status frame, once received
    this.sent = [];            // the requests (JSON text or encodings), the latest MAX_LOG
    this.requests = [];        // the same as JSON objects, where known
    this.roundTrips = [];      // ms from sending a request to its answer arriving (timed in the worker)
    this.pageRoundTrips = [];  // the same, until the page's thread handled the answer
    worker.onmessage = ({ data }) => (data.closed ? this.onClose(data.closed) : this.onAnswer(data));
  }

  get open() {
    return this.isOpen;
  }

  // Sends one request message (an object: JSON; a Uint8Array: its proto
  // encoding, with `asJson` its JSON form for the log); resolves with its
  // answer (an object, or for a binary request the answer's encoding as an
  // ArrayBuffer).
  request(message, asJson = undefined) {
    if (!this.isOpen) return Promise.reject(this.failure() ?? new Error('the session is closed'));
    const binary = message instanceof Uint8Array;
    const payload = binary ? message : JSON.stringify(message);
    return new Promise((resolve, reject) => {
      this.waiting.push({ resolve, reject, sent: performance.now() });
      this.worker.postMessage({ send: payload });
      keep(this.sent, payload);
      keep(this.requests, binary ? asJson ?? null : message);
    });
  }

  // Ends the session (the server answers what is left, then closes).
  close() {
    if (this.isOpen) this.worker.postMessage({ close: true });
  }

  onAnswer({ answer, ms }) {
    const message = answer instanceof ArrayBuffer ? answer : JSON.parse(answer);
    if (!(message instanceof ArrayBuffer) && typeof message.code === 'number' && Array.isArray(message.details) && !('positions' in message)) {
      this.status = message;  // the session failed: the close follows
      return;
    }
    const next = this.waiting.shift();
    if (!next) return;
    keep(this.roundTrips, ms);
    keep(this.pageRoundTrips, performance.now() - next.sent);
    next.resolve(message);
  }

  failure() {
    if (!this.status) return null;
    const error = new Error(this.status.message);
    error.code = this.status.code;
    return error;
  }

  onClose({ code, reason }) {
    this.isOpen = false;
    this.worker.terminate();
    const error = this.failure() ??
      new Error(code === 1000 ? 'the session ended' : `the session closed (${code} ${reason})`);
    for (const w of this.waiting.splice(0)) w.reject(error);
  }
}

function keep(list, value) {
  list.push(value);
  if (list.length > MAX_LOG) list.splice(0, list.length - MAX_LOG);
}
