// Typed errors: every failed call (unary or a stream mid-way) throws an
// ArmatureError, or the subclass for its status, carrying the gRPC status code
// and the server's message (which names the field, clip, joint... at fault).
import { Code, ConnectError } from '@connectrpc/connect';

export { Code };

export class ArmatureError extends Error {
  /** The gRPC status code (Code.NotFound === 5, as in gRPC). */
  readonly code: Code;
  /** Its name as in gRPC, e.g. "NOT_FOUND". */
  readonly status: string;
  /** The server's message, without the status in front. */
  readonly rawMessage: string;
  /** Response headers and trailers of the failed call. */
  readonly metadata: Headers;

  constructor(code: Code, rawMessage: string, metadata: Headers = new Headers(), options?: { cause?: unknown }) {
    const status = statusName(code);
    super(`${status}: ${rawMessage}`, options);
    this.name = new.target.name;
    this.code = code;
    this.status = status;
    this.rawMessage = rawMessage;
    this.metadata = metadata;
  }
}

export class InvalidArgumentError extends ArmatureError {}
export class NotFoundError extends ArmatureError {}
export class AlreadyExistsError extends ArmatureError {}
export class PermissionDeniedError extends ArmatureError {}
export class UnauthenticatedError extends ArmatureError {}
export class ResourceExhaustedError extends ArmatureError {}
export class FailedPreconditionError extends ArmatureError {}
export class DeadlineExceededError extends ArmatureError {}
export class UnavailableError extends ArmatureError {}

const SUBCLASS: Partial<Record<Code, typeof ArmatureError>> = {
  [Code.InvalidArgument]: InvalidArgumentError,
  [Code.NotFound]: NotFoundError,
  [Code.AlreadyExists]: AlreadyExistsError,
  [Code.PermissionDenied]: PermissionDeniedError,
  [Code.Unauthenticated]: UnauthenticatedError,
  [Code.ResourceExhausted]: ResourceExhaustedError,
  [Code.FailedPrecondition]: FailedPreconditionError,
  [Code.DeadlineExceeded]: DeadlineExceededError,
  [Code.Unavailable]: UnavailableError,
};

/** The ArmatureError of the subclass for a status the server sent outside gRPC (a WebSocket session's last frame). */
export function errorForStatus(code: Code, message: string): ArmatureError {
  const Type = SUBCLASS[code] ?? ArmatureError;
  return new Type(code, message);
}

/** "NOT_FOUND" for Code.NotFound: gRPC's spelling of connect's enum name. */
export function statusName(code: Code): string {
  return (Code[code] ?? 'UNKNOWN').replace(/([a-z])([A-Z])/g, '$1_$2').toUpperCase();
}

/** Any thrown value as an ArmatureError of the subclass for its status. */
export function toArmatureError(thrown: unknown): ArmatureError {
  if (thrown instanceof ArmatureError) return thrown;
  const e = ConnectError.from(thrown);
  const Type = SUBCLASS[e.code] ?? ArmatureError;
  return new Type(e.code, e.rawMessage, e.metadata, { cause: thrown });
}
