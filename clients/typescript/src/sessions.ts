// Interactive sessions (IkSession, DeformSession) over a WebSocket on the
// server's REST path, in binary frames (each request's and answer's proto
// encoding): what gRPC-Web over HTTP/1.1 cannot carry. Browsers have
// WebSocket (or WorkerWebSocket, in a worker of its own); in node pass the
// `ws` package's, or run node with --experimental-websocket (node 20) or
// node 22+. A failed session rejects with the ArmatureError of its status.
import { create, fromBinary, toBinary } from '@bufbuild/protobuf';
import type { DescMessage, MessageInitShape, MessageShape } from '@bufbuild/protobuf';

import { ArmatureError, Code, errorForStatus } from './errors.js';
import { DeformResponseSchema, DeformSessionRequestSchema } from './gen/armature/v1/deform_pb.js';
import type { DeformResponse, DeformSessionStartSchema } from './gen/armature/v1/deform_pb.js';
import { IkSessionRequestSchema, SolveIkResponseSchema } from './gen/armature/v1/ik_pb.js';
import type { SolveIkRequest, SolveIkRequestSchema, SolveIkResponse } from './gen/armature/v1/ik_pb.js';
import { SessionLog } from './session_log.js';

/** What a session uses of a WebSocket: the browser's, node's, the `ws` package's or WorkerWebSocket. */
export interface SessionSocket {
  binaryType: BinaryType;
  readonly readyState: number;
  onopen: ((event: Event) => void) | null;
  onerror: ((event: Event) => void) | null;
  /** `roundTripMs`: the answer's round trip, when the socket timed it itself (WorkerWebSocket). */
  onmessage: ((event: MessageEvent & { roundTripMs?: number }) => void) | null;
  onclose: ((event: CloseEvent) => void) | null;
  send(data: Uint8Array): void;
  close(code?: number): void;
}

/** The WebSocket constructor to use: the global one when absent. */
export type WebSocketConstructor = new (url: string, protocols?: string | string[]) => SessionSocket;

export interface SessionOptions {
  /** Sent as the subprotocol "bearer.<token>" (browsers cannot set Authorization on a WebSocket). */
  token?: string;
  WebSocket?: WebSocketConstructor;
  /** Keeps the latest `keepLog` requests and round trips in `session.log` (none when absent). */
  keepLog?: number;
}

const OPEN = 1;

/** A session's WebSocket at `url`, open, in binary (the token as the subprotocol "bearer.<token>"). */
export async function openSocket(url: string, options: SessionOptions): Promise<SessionSocket> {
  const Socket = options.WebSocket ?? (globalThis.WebSocket as WebSocketConstructor | undefined);
  if (!Socket) throw new Error('no WebSocket: pass options.WebSocket (the ws package) or use node 22+');
  const socket = new Socket(url, options.token ? [`bearer.${options.token}`] : []);
  socket.binaryType = 'arraybuffer';
  await new Promise<void>((resolve, reject) => {
    socket.onopen = () => resolve();
    socket.onerror = () => reject(new ArmatureError(Code.Unavailable, `could not open a session at ${url}`));
  });
  socket.onerror = null;
  return socket;
}

// A request sent and not answered yet.
interface Waiting<Res extends DescMessage> {
  resolve: (answer: MessageShape<Res>) => void;
  reject: (e: Error) => void;
  sentAt: number;
}

/** One open session: each send gets one answer, in order. */
export class Session<Req extends DescMessage, Res extends DescMessage> {
  /** The requests sent and their round trips, with options.keepLog. */
  readonly log: SessionLog<Req> | null;
  private readonly waiting: Waiting<Res>[] = [];
  private failure: ArmatureError | null = null;
  private closed: Promise<void>;

  private constructor(readonly url: string, private readonly socket: SessionSocket, private readonly request: Req,
                      private readonly response: Res, keepLog: number | undefined) {
    this.log = keepLog ? new SessionLog(url, request, keepLog) : null;
    socket.onmessage = (event) => this.onFrame(event);
    this.closed = new Promise((resolve) => {
      socket.onclose = (event: CloseEvent) => {
        const reason = event.reason ? ' ' + event.reason : '';
        const error = this.failure ?? new ArmatureError(Code.Unavailable, `the session closed (${event.code}${reason})`);
        for (const w of this.waiting.splice(0)) w.reject(error);
        resolve();
      };
    });
  }

  static async open<Req extends DescMessage, Res extends DescMessage>(
    url: string, request: Req, response: Res, options: SessionOptions,
  ): Promise<Session<Req, Res>> {
    return new Session(url, await openSocket(url, options), request, response, options.keepLog);
  }

  /** The session takes requests (it has neither failed nor been closed). */
  get isOpen(): boolean {
    return this.socket.readyState === OPEN;
  }

  /** Requests sent and not answered yet. */
  get pending(): number {
    return this.waiting.length;
  }

  /** Sends one request; resolves with its answer. */
  send(message: MessageInitShape<Req>): Promise<MessageShape<Res>> {
    if (!this.isOpen) {
      return Promise.reject(this.failure ?? new ArmatureError(Code.Unavailable, 'the session is closed'));
    }
    const request = create(this.request, message);
    const frame = toBinary(this.request, request);
    return new Promise((resolve, reject) => {
      this.waiting.push({ resolve, reject, sentAt: performance.now() });
      this.socket.send(frame);
      this.log?.requested(frame, request);
    });
  }

  /** Ends the session; resolves once the server closed it. */
  close(): Promise<void> {
    if (this.socket.readyState <= OPEN) this.socket.close(1000);
    return this.closed;
  }

  // Every request goes in a binary frame, so every answer comes in one: a
  // text frame is the status of a failed session (the close follows).
  private onFrame(event: MessageEvent & { roundTripMs?: number }): void {
    if (typeof event.data === 'string') {
      const { code, message } = JSON.parse(event.data) as { code: Code; message: string };
      this.failure = errorForStatus(code, message);
      return;
    }
    const next = this.waiting.shift();
    if (!next) return;
    const answer = fromBinary(this.response, new Uint8Array(event.data as ArrayBuffer));
    const handledMs = performance.now() - next.sentAt;
    this.log?.answered(event.roundTripMs ?? handledMs, handledMs);
    next.resolve(answer);
  }
}

/** The WebSocket URL of a REST path on the server at `baseUrl` (http → ws, https → wss). */
export const wsUrl = (baseUrl: string, path: string): string => baseUrl.replace(/\/+$/, '').replace(/^http/, 'ws') + path;

export type IkSession = Session<typeof IkSessionRequestSchema, typeof SolveIkResponseSchema>;
export type DeformSession = Session<typeof DeformSessionRequestSchema, typeof DeformResponseSchema>;

/** Opens an IK session; resolves with it and the start's answer. Later: `send({targets: [...]})`. */
export async function openIkSession(baseUrl: string, start: MessageInitShape<typeof SolveIkRequestSchema>,
                                    options: SessionOptions = {}): Promise<{ session: IkSession; first: SolveIkResponse }> {
  const skeleton = (start as Partial<SolveIkRequest>).skeleton ?? '';
  const session = await Session.open(wsUrl(baseUrl, `/v1/skeletons/${encodeURIComponent(skeleton)}:ikSession`),
                                     IkSessionRequestSchema, SolveIkResponseSchema, options);
  return { session, first: await session.send({ start }) };
}

/** Opens a deformation session; resolves with it and the setup's answer (the rest shape). Later: `send({message: {case: 'move', value: {positions}}})`. */
export async function openDeformSession(baseUrl: string, start: MessageInitShape<typeof DeformSessionStartSchema>,
                                        options: SessionOptions = {}): Promise<{ session: DeformSession; first: DeformResponse }> {
  const session = await Session.open(wsUrl(baseUrl, '/v1/meshes:deformSession'), DeformSessionRequestSchema,
                                     DeformResponseSchema, options);
  return { session, first: await session.send({ message: { case: 'start', value: start } }) };
}
