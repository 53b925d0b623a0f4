// A crowd (CrowdService.CrowdSession) over a WebSocket on its REST path,
// /v1/crowds:session, in binary frames: commands (add, update, remove) go out
// whenever the caller sends them, and one frame a tick comes back, its poses
// decoded (crowd_decoder.ts) to LOCAL poses. A refused command does not end
// the session: it comes back in a frame's `errors`, naming the character. A
// failed session (a text frame with its status, then the close) ends
// `frames()` with the ArmatureError of that status.
import { create, fromBinary, toBinary } from '@bufbuild/protobuf';
import type { MessageInitShape } from '@bufbuild/protobuf';

import { CrowdDecoder } from './crowd_decoder.js';
import type { CrowdPoses } from './crowd_decoder.js';
import { ArmatureError, Code, errorForStatus } from './errors.js';
import { CrowdCommandSchema, CrowdFrameSchema } from './gen/armature/v1/crowd_pb.js';
import type {
  CrowdCharacterSchema, CrowdError, CrowdFrame, CrowdStartSchema, CrowdTickStats,
} from './gen/armature/v1/crowd_pb.js';
import { openSocket, wsUrl } from './sessions.js';
import type { SessionOptions, SessionSocket } from './sessions.js';

/** One tick of a crowd: the characters it updates, decoded, and the server's figures. */
export interface CrowdTick {
  tick: number;
  /** Session seconds: tick / fps. */
  time: number;
  /** Seconds since the first frame was due. */
  wallTime: number;
  poses: CrowdPoses;
  /** Commands refused since the last frame (e.g. "character 7: …"). */
  errors: CrowdError[];
  stats?: CrowdTickStats;
  /** The frame as received (its new layouts included). */
  frame: CrowdFrame;
}

export type CrowdCharacterInit = MessageInitShape<typeof CrowdCharacterSchema>;

const OPEN = 1;

export class CrowdSession {
  readonly decoder = new CrowdDecoder();
  private readonly ticks: CrowdTick[] = [];
  private wake: (() => void) | null = null;
  private ended = false;
  private failure: ArmatureError | null = null;
  private readonly closed: Promise<void>;

  private constructor(readonly url: string, private readonly socket: SessionSocket) {
    socket.onmessage = (event) => this.onFrame(event.data);
    this.closed = new Promise((resolve) => {
      socket.onclose = (event: CloseEvent) => {
        // A close other than normal without a status before it is a failure too.
        if (!this.failure && event.code !== 1000 && event.code !== 1005) {
          this.failure = new ArmatureError(Code.Unavailable, `the crowd session closed (${event.code} ${event.reason})`);
        }
        this.ended = true;
        this.wake?.();
        resolve();
      };
    });
  }

  /** Opens a crowd session at the server `baseUrl` and sends its start. */
  static async open(baseUrl: string, start: MessageInitShape<typeof CrowdStartSchema> = {},
                    options: SessionOptions = {}): Promise<CrowdSession> {
    const url = wsUrl(baseUrl, '/v1/crowds:session');
    const session = new CrowdSession(url, await openSocket(url, options));
    session.command({ command: { case: 'start', value: start } });
    return session;
  }

  /** The session takes commands (it has neither ended nor been closed). */
  get isOpen(): boolean {
    return this.socket.readyState === OPEN;
  }

  add(character: CrowdCharacterInit): void {
    this.command({ command: { case: 'add', value: character } });
  }

  /** Replaces every field of the character `character.id`. */
  update(character: CrowdCharacterInit): void {
    this.command({ command: { case: 'update', value: character } });
  }

  remove(id: number): void {
    this.command({ command: { case: 'remove', value: id } });
  }

  /** The ticks as they come, until the server ends the session or it is closed; throws a failed session's error. */
  async *frames(): AsyncGenerator<CrowdTick> {
    while (true) {
      const next = this.ticks.shift();
      if (next) {
        yield next;
        continue;
      }
      if (this.ended) break;
      await new Promise<void>((resolve) => (this.wake = resolve));
      this.wake = null;
    }
    if (this.failure) throw this.failure;
  }

  /** Ends the session (the frames already on their way still arrive); resolves once the server closed it. */
  close(): Promise<void> {
    if (this.socket.readyState <= OPEN) this.socket.close(1000);
    return this.closed;
  }

  private command(init: MessageInitShape<typeof CrowdCommandSchema>): void {
    if (!this.isOpen) throw this.failure ?? new ArmatureError(Code.Unavailable, 'the crowd session is closed');
    this.socket.send(toBinary(CrowdCommandSchema, create(CrowdCommandSchema, init)));
  }

  // Commands go in binary frames, so frames come in binary: a text frame is a failed session's status.
  private onFrame(data: unknown): void {
    if (typeof data === 'string') {
      const { code, message } = JSON.parse(data) as { code: Code; message: string };
      this.failure = errorForStatus(code, message);
      return;
    }
    try {
      const frame = fromBinary(CrowdFrameSchema, new Uint8Array(data as ArrayBuffer));
      this.ticks.push({
        tick: Number(frame.tick), time: frame.time, wallTime: frame.wallTime, poses: this.decoder.decode(frame),
        errors: frame.errors, stats: frame.stats, frame,
      });
    } catch (e) {  // a frame that does not decode ends the session with its error
      this.failure = e instanceof ArmatureError ? e : new ArmatureError(Code.Internal, `crowd frame: ${e}`);
      this.socket.close(1000);
    }
    this.wake?.();
  }
}

/** Opens a crowd session: `CrowdSession.open`. */
export const openCrowdSession = CrowdSession.open.bind(CrowdSession);
