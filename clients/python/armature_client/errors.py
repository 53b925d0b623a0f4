"""Typed errors: every failed call raises an ArmatureError carrying the gRPC status."""
import grpc


class ArmatureError(Exception):
    """A call failed. `.code` is the grpc.StatusCode, `.message` the server's message."""

    code = grpc.StatusCode.UNKNOWN

    def __init__(self, code, message):
        super().__init__(f"{code.name}: {message}")
        self.code = code
        self.message = message


class Cancelled(ArmatureError): pass  # noqa: E701
class Unknown(ArmatureError): pass  # noqa: E701
class InvalidArgument(ArmatureError): pass  # noqa: E701
class DeadlineExceeded(ArmatureError): pass  # noqa: E701
class NotFound(ArmatureError): pass  # noqa: E701
class AlreadyExists(ArmatureError): pass  # noqa: E701
class PermissionDenied(ArmatureError): pass  # noqa: E701
class ResourceExhausted(ArmatureError): pass  # noqa: E701
class FailedPrecondition(ArmatureError): pass  # noqa: E701
class Aborted(ArmatureError): pass  # noqa: E701
class OutOfRange(ArmatureError): pass  # noqa: E701
class Unimplemented(ArmatureError): pass  # noqa: E701
class Internal(ArmatureError): pass  # noqa: E701
class Unavailable(ArmatureError): pass  # noqa: E701
class DataLoss(ArmatureError): pass  # noqa: E701
class Unauthenticated(ArmatureError): pass  # noqa: E701


_BY_CODE = {
    grpc.StatusCode.CANCELLED: Cancelled,
    grpc.StatusCode.UNKNOWN: Unknown,
    grpc.StatusCode.INVALID_ARGUMENT: InvalidArgument,
    grpc.StatusCode.DEADLINE_EXCEEDED: DeadlineExceeded,
    grpc.StatusCode.NOT_FOUND: NotFound,
    grpc.StatusCode.ALREADY_EXISTS: AlreadyExists,
    grpc.StatusCode.PERMISSION_DENIED: PermissionDenied,
    grpc.StatusCode.RESOURCE_EXHAUSTED: ResourceExhausted,
    grpc.StatusCode.FAILED_PRECONDITION: FailedPrecondition,
    grpc.StatusCode.ABORTED: Aborted,
    grpc.StatusCode.OUT_OF_RANGE: OutOfRange,
    grpc.StatusCode.UNIMPLEMENTED: Unimplemented,
    grpc.StatusCode.INTERNAL: Internal,
    grpc.StatusCode.UNAVAILABLE: Unavailable,
    grpc.StatusCode.DATA_LOSS: DataLoss,
    grpc.StatusCode.UNAUTHENTICATED: Unauthenticated,
}


def error_for(code, message):
    """The ArmatureError subclass for a status code."""
    return _BY_CODE.get(code, ArmatureError)(code, message)


def from_rpc_error(e):
    """Turns a grpc.RpcError into the typed error."""
    code = e.code() if hasattr(e, "code") else grpc.StatusCode.UNKNOWN
    details = e.details() if hasattr(e, "details") else str(e)
    return error_for(code or grpc.StatusCode.UNKNOWN, details or "")
