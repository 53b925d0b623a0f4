// What a session sent and how long each answer took, for inspection and
// timing (the viewer's drags log theirs; web.session_e2e replays the frames
// and the requests, and compares the round trips with gRPC's).
import { toJson } from '@bufbuild/protobuf';
import type { DescMessage, JsonValue, MessageShape } from '@bufbuild/protobuf';

/** The latest `size` requests of a session and the round trips of their answers. */
export class SessionLog<Req extends DescMessage> {
  /** Each request's frame as sent (its proto encoding). */
  readonly sent: Uint8Array[] = [];
  /** Ms from sending a request to its answer arriving at the socket (timed in the socket's worker, if it has one). */
  readonly roundTrips: number[] = [];
  /** Ms from sending a request to its answer being handled by the session's thread. */
  readonly pageRoundTrips: number[] = [];
  private readonly messages: MessageShape<Req>[] = [];

  constructor(readonly url: string, private readonly schema: Req, private readonly size: number) {}

  /** The requests as proto3 JSON (made when asked: sending stays cheap). */
  get requests(): JsonValue[] {
    return this.messages.map((message) => toJson(this.schema, message));
  }

  requested(frame: Uint8Array, message: MessageShape<Req>): void {
    this.keep(this.sent, frame);
    this.keep(this.messages, message);
  }

  answered(roundTripMs: number, handledMs: number): void {
    this.keep(this.roundTrips, roundTripMs);
    this.keep(this.pageRoundTrips, handledMs);
  }

  private keep<T>(list: T[], value: T): void {
    list.push(value);
    if (list.length > this.size) list.splice(0, list.length - this.size);
  }
}
