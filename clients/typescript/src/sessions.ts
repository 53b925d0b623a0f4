// Interactive sessions (IkSession, DeformSession) over a WebSocket on the
// server's REST path, in binary frames (each request's and answer's proto
// encoding): what gRPC-Web over HTTP/1.1 cannot carry. Browsers have
// WebSocket; in node pass the `ws` package's, or run node with
// --experimental-websocket (node 20) or node 22+. A failed session rejects
// with the ArmatureError of its status (the server's last text frame).
import { create, fromBinary, toBinary } from '@bufbuild/protobuf';
import type { DescMessage, MessageInitShape, MessageShape } from '@bufbuild/protobuf';

import { ArmatureError, Code, errorForStatus } from './errors.js';
import { DeformResponseSchema, DeformSessionRequestSchema } from './gen/armature/v1/deform_pb.js';
import type { DeformResponse, DeformSessionStartSchema } from './gen/armature/v1/deform_pb.js';
import { IkSessionRequestSchema, SolveIkResponseSchema } from './gen/armature/v1/ik_pb.js';
import type { SolveIkRequest, SolveIkRequestSchema, SolveIkResponse } from './gen/armature/v1/ik_pb.js';

/** The WebSocket constructor to use: the global one when absent. */
export type WebSocketConstructor = new (url: string, protocols?: string | string[]) => WebSocket;

export interface SessionOptions {
  /** Sent as the subprotocol "bearer.<token>" (browsers cannot set Authorization on a WebSocket). */
  token?: string;
  WebSocket?: WebSocketConstructor;
}

/** One open session: each send gets one answer, in order. */
export class Session<Req extends DescMessage, Res extends DescMessage> {
  private readonly waiting: { resolve: (r: MessageShape<Res>) => void; reject: (e: Error) => void }[] = [];
  private failure: ArmatureError | null = null;
  private closed: Promise<void>;

  private constructor(private readonly socket: WebSocket, private readonly request: Req,
                      private readonly response: Res) {
    socket.binaryType = 'arraybuffer';
    socket.onmessage = (event: MessageEvent) => {
      if (typeof event.data === 'string') {  // the status of a failed session; the close follows
        const { code, message } = JSON.parse(event.data) as { code: Code; message: string };
        this.failure = errorForStatus(code, message);
        return;
      }
      this.waiting.shift()?.resolve(fromBinary(this.response, new Uint8Array(event.data as ArrayBuffer)));
    };
    this.closed = new Promise((resolve) => {
      socket.onclose = (event: CloseEvent) => {
        const error = this.failure ??
          new ArmatureError(Code.Unavailable, `the session closed (${event.code}${event.reason ? ' ' + event.reason : ''})`);
        for (const w of this.waiting.splice(0)) w.reject(error);
        resolve();
      };
    });
  }

  static async open<Req extends DescMessage, Res extends DescMessage>(
    url: string, request: Req, response: Res, options: SessionOptions,
  ): Promise<Session<Req, Res>> {
    const Socket = options.WebSocket ?? (globalThis.WebSocket as WebSocketConstructor | undefined);
    if (!Socket) throw new Error('no WebSocket: pass options.WebSocket (the ws package) or use node 22+');
    const socket = new Socket(url, options.token ? [`bearer.${options.token}`] : []);
    await new Promise<void>((resolve, reject) => {
      socket.onopen = () => resolve();
      socket.onerror = () => reject(new ArmatureError(Code.Unavailable, `could not open a session at ${url}`));
    });
    socket.onerror = null;
    return new Session(socket, request, response);
  }

  /** Sends one request; resolves with its answer. */
  send(message: MessageInitShape<Req>): Promise<MessageShape<Res>> {
    if (this.socket.readyState !== 1) return Promise.reject(this.failure ?? new ArmatureError(Code.Unavailable, 'the session is closed'));
    return new Promise((resolve, reject) => {
      this.waiting.push({ resolve, reject });
      this.socket.send(toBinary(this.request, create(this.request, message)));
    });
  }

  /** Ends the session; resolves once the server closed it. */
  close(): Promise<void> {
    if (this.socket.readyState <= 1) this.socket.close(1000);
    return this.closed;
  }
}

const wsUrl = (baseUrl: string, path: string) => baseUrl.replace(/\/+$/, '').replace(/^http/, 'ws') + path;

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
