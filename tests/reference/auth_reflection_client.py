"""With --auth-token-file, grpcio (a client that is not ours) finds reflection
and health open, and the API closed without the bearer token.

usage: auth_reflection_client.py SERVER_BIN [v1alpha|v1]   (the reflection version; default v1alpha)
"""
import os
import sys
import tempfile

import grpc

sys.path.insert(0, os.path.dirname(__file__))
from reflection_client import reflection_module, reflection_proto  # noqa: E402
from server_fixture import Server  # noqa: E402

TOKEN = "py-token-123"


def main():
    version = sys.argv[2] if len(sys.argv) > 2 else "v1alpha"
    if not os.path.exists(reflection_proto(version)):
        print(f"SKIP: grpc-proto's {version} reflection.proto is not installed")
        return 0
    rpb = reflection_module(version)
    failures = []

    def check(cond, what):
        print(("ok   " if cond else "FAIL ") + what)
        if not cond:
            failures.append(what)

    with tempfile.TemporaryDirectory() as d:
        token_file = os.path.join(d, "token")
        with open(token_file, "w") as f:
            f.write(TOKEN + "\n")
        with Server(sys.argv[1], ["--auth-token-file", token_file]) as server:
            channel = grpc.insecure_channel(server.target)
            info = channel.stream_stream(
                f"/grpc.reflection.{version}.ServerReflection/ServerReflectionInfo",
                request_serializer=rpb.ServerReflectionRequest.SerializeToString,
                response_deserializer=rpb.ServerReflectionResponse.FromString)
            reply = list(info(iter([rpb.ServerReflectionRequest(list_services="")]), timeout=10))[0]
            services = [s.name for s in reply.list_services_response.service]
            check("armature.v1.PoseService" in services, f"reflection {version} answers without a token")
            files = list(info(iter([rpb.ServerReflectionRequest(file_containing_symbol="armature.v1.PoseService")]),
                              timeout=10))[0].file_descriptor_response.file_descriptor_proto
            check(len(files) > 0, f"reflection {version} describes PoseService without a token")

            # Raw bytes: an empty EvaluateClipRequest. Refused before it is even parsed.
            evaluate = channel.unary_unary("/armature.v1.PoseService/EvaluateClip")
            try:
                evaluate(b"", timeout=10)
                check(False, "EvaluateClip without a token is refused")
            except grpc.RpcError as e:
                check(e.code() == grpc.StatusCode.UNAUTHENTICATED,
                      f"EvaluateClip without a token is UNAUTHENTICATED ({e.code()}: {e.details()})")
            try:
                evaluate(b"", timeout=10, metadata=[("authorization", "Bearer " + TOKEN)])
                check(False, "an empty request with the token reaches the handler")
            except grpc.RpcError as e:
                # Past the gate: the handler answers (no clip named '').
                check(e.code() == grpc.StatusCode.NOT_FOUND,
                      f"with the token the call reaches the handler ({e.code()}: {e.details()})")
    print(f"{len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
