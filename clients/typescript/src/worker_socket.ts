// A WebSocket that lives in a small dedicated worker (browsers), for
// sessions: answers are received, and their round trips timed, as they
// arrive, even while the page's thread is busy drawing; the page then
// handles them in order. Pass it as a session's `WebSocket` option.
import type { SessionSocket } from './sessions.js';

// The worker: owns the WebSocket, stamps each answer with its round trip.
// Stringified into the worker, so it uses nothing from outside itself.
function socketWorker() {
  let socket: WebSocket | null = null;
  const sentAt: number[] = [];  // send times of the requests not yet answered, in order
  self.onmessage = ({ data }: MessageEvent) => {
    if (data.open) {
      const opened = new WebSocket(data.open, data.protocols);
      socket = opened;
      opened.binaryType = 'arraybuffer';
      opened.onopen = () => self.postMessage({ opened: true });
      opened.onerror = () => self.postMessage({ failed: true });
      opened.onmessage = (e: MessageEvent) => {
        // A text frame is a failed session's status: it answers no request.
        if (typeof e.data === 'string') return self.postMessage({ answer: e.data });
        const answer = { answer: e.data, roundTripMs: performance.now() - (sentAt.shift() ?? 0) };
        self.postMessage(answer, { transfer: [e.data as ArrayBuffer] });
      };
      opened.onclose = (e: CloseEvent) => self.postMessage({ closed: { code: e.code, reason: e.reason } });
    } else if (data.send !== undefined) {
      sentAt.push(performance.now());
      socket?.send(data.send);
    } else if (data.close) {
      socket?.close(data.close);
    }
  };
}
let workerUrl: string | null = null;

const CONNECTING = 0, OPEN = 1, CLOSING = 2, CLOSED = 3;

/** A WebSocket run in a dedicated worker; its answers carry `roundTripMs`, timed there. */
export class WorkerWebSocket implements SessionSocket {
  binaryType: BinaryType = 'arraybuffer';
  readyState = CONNECTING;
  onopen: ((event: Event) => void) | null = null;
  onerror: ((event: Event) => void) | null = null;
  onmessage: ((event: MessageEvent) => void) | null = null;
  onclose: ((event: CloseEvent) => void) | null = null;
  private readonly worker: Worker;

  constructor(url: string, protocols: string | string[] = []) {
    workerUrl ??= URL.createObjectURL(new Blob([`(${socketWorker})()`], { type: 'text/javascript' }));
    this.worker = new Worker(workerUrl);
    this.worker.onmessage = ({ data }: MessageEvent) => this.fromWorker(data);
    this.worker.postMessage({ open: url, protocols });
  }

  send(data: Uint8Array): void {
    this.worker.postMessage({ send: data });
  }

  close(code = 1000): void {
    if (this.readyState > OPEN) return;
    this.readyState = CLOSING;
    this.worker.postMessage({ close: code });
  }

  private fromWorker(data: { opened?: true; failed?: true; answer?: unknown; roundTripMs?: number;
                             closed?: { code: number; reason: string } }): void {
    if (data.opened) {
      this.readyState = OPEN;
      this.onopen?.(new Event('open'));
    } else if (data.failed) {
      this.onerror?.(new Event('error'));
    } else if (data.closed) {
      this.readyState = CLOSED;
      this.worker.terminate();
      this.onclose?.(new CloseEvent('close', data.closed));
    } else {
      const event = new MessageEvent('message', { data: data.answer });
      this.onmessage?.(Object.assign(event, { roundTripMs: data.roundTripMs }));
    }
  }
}
