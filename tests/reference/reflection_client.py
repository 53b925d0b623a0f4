"""A client that has none of Armature's .proto files: it learns the API from
server reflection, then calls EvaluateClip and the health check with grpcio.

usage: reflection_client.py SERVER_BIN
"""
import os
import sys
import tempfile

import grpc
from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

sys.path.insert(0, os.path.dirname(__file__))
from server_fixture import Server  # noqa: E402

REFLECTION_PROTO = "/usr/share/grpc-proto/grpc/reflection/v1alpha/reflection.proto"


def reflection_module():
    """Generates the reflection protocol's Python code (from Debian's grpc-proto)."""
    from grpc_tools import protoc
    out = tempfile.mkdtemp(prefix="reflection-py-")
    include = "/usr/share/grpc-proto"
    if protoc.main(["protoc", f"-I{include}", f"--python_out={out}", REFLECTION_PROTO]) != 0:
        raise RuntimeError("protoc failed")
    # Loaded by path: a "grpc" package on sys.path would shadow grpcio's.
    import importlib.util
    path = os.path.join(out, "grpc", "reflection", "v1alpha", "reflection_pb2.py")
    spec = importlib.util.spec_from_file_location("reflection_pb2", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main():
    server_bin = sys.argv[1]
    if not os.path.exists(REFLECTION_PROTO):
        print("SKIP: grpc-proto's reflection.proto is not installed")
        return 0
    rpb = reflection_module()
    failures, passes = [], []

    def check(cond, what):
        print(("ok   " if cond else "FAIL ") + what)
        (passes if cond else failures).append(what)

    with Server(server_bin) as server:
        channel = grpc.insecure_channel(server.target)
        info = channel.stream_stream(
            "/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
            request_serializer=rpb.ServerReflectionRequest.SerializeToString,
            response_deserializer=rpb.ServerReflectionResponse.FromString)

        def ask(**kw):
            return list(info(iter([rpb.ServerReflectionRequest(**kw)])))[0]

        services = [s.name for s in ask(list_services="").list_services_response.service]
        print("services:", services)
        for s in ("armature.v1.AssetService", "armature.v1.PoseService", "grpc.health.v1.Health"):
            check(s in services, f"reflection lists {s}")

        # Fetch the files defining PoseService (and what they import) into a pool.
        pool = descriptor_pool.DescriptorPool()
        pending = [f for f in ask(file_containing_symbol="armature.v1.PoseService")
                   .file_descriptor_response.file_descriptor_proto]
        added = set()
        while pending:
            progress = False
            for raw in list(pending):
                fdp = descriptor_pb2.FileDescriptorProto.FromString(raw)
                if fdp.name in added:
                    pending.remove(raw)
                    continue
                missing = [d for d in fdp.dependency if d not in added]
                if missing:
                    for d in missing:
                        if not any(descriptor_pb2.FileDescriptorProto.FromString(p).name == d for p in pending):
                            pending += list(ask(file_by_filename=d).file_descriptor_response.file_descriptor_proto)
                    continue
                pool.Add(fdp)
                added.add(fdp.name)
                pending.remove(raw)
                progress = True
            if not progress and pending:
                raise RuntimeError("could not resolve descriptor dependencies")
        service = pool.FindServiceByName("armature.v1.PoseService")
        method = service.methods_by_name["EvaluateClip"]
        factory = message_factory.MessageFactory(pool)
        Request = factory.GetPrototype(method.input_type)
        Response = factory.GetPrototype(method.output_type)
        request = Request(clip="demo_walk", times=[0.25, 0.5])
        request.space = method.input_type.fields_by_name["space"].enum_type.values_by_name["WORLD"].number
        call = channel.unary_unary("/armature.v1.PoseService/EvaluateClip",
                                   request_serializer=Request.SerializeToString,
                                   response_deserializer=Response.FromString)
        response = call(request, timeout=10)
        check(len(response.poses) == 2, "EvaluateClip returns one pose per time")
        check(len(response.poses[0].translations) == 3 * len(response.joints) > 0,
              "each pose has 3 translation values per joint")
        check(response.skeleton == "demo_walk", "the pose names its skeleton")
        try:
            bad = Request(clip="demo_walk", times=[-1.0])
            call(bad, timeout=10)
            check(False, "a negative time is refused")
        except grpc.RpcError as e:
            check(e.code() == grpc.StatusCode.INVALID_ARGUMENT and "times[0]" in e.details(),
                  f"a negative time is INVALID_ARGUMENT naming the field ({e.details()})")

        # Health, through the same reflected descriptors.
        hfile = ask(file_containing_symbol="grpc.health.v1.Health").file_descriptor_response.file_descriptor_proto
        hpool = descriptor_pool.DescriptorPool()
        for raw in hfile:
            hpool.Add(descriptor_pb2.FileDescriptorProto.FromString(raw))
        hmethod = hpool.FindServiceByName("grpc.health.v1.Health").methods_by_name["Check"]
        hf = message_factory.MessageFactory(hpool)
        HReq, HResp = hf.GetPrototype(hmethod.input_type), hf.GetPrototype(hmethod.output_type)
        health = channel.unary_unary("/grpc.health.v1.Health/Check", request_serializer=HReq.SerializeToString,
                                     response_deserializer=HResp.FromString)(HReq(), timeout=10)
        serving = hmethod.output_type.fields_by_name["status"].enum_type.values_by_name["SERVING"].number
        check(health.status == serving, "health reports SERVING")
    print(f"{len(passes)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
