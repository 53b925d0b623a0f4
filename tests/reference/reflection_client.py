"""A client that has none of Armature's .proto files: it learns the API from
server reflection, then calls EvaluateClip and the health check with grpcio.

usage: reflection_client.py SERVER_BIN [v1alpha|v1]   (the reflection version; default v1alpha)
"""
import os
import sys
import tempfile

import grpc
from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

sys.path.insert(0, os.path.dirname(__file__))
from server_fixture import Server  # noqa: E402

GRPC_PROTO = "/usr/share/grpc-proto"
REFLECTION_PROTO = GRPC_PROTO + "/grpc/reflection/v1alpha/reflection.proto"
# google.api.http, the one extension Armature's protos declare (on google.protobuf.MethodOptions).
HTTP_RULE_EXTENSION = 72295728


def reflection_proto(version="v1alpha"):
    return f"{GRPC_PROTO}/grpc/reflection/{version}/reflection.proto"


def reflection_module(version="v1alpha"):
    """Generates the reflection protocol's Python code (from Debian's grpc-proto,
    not from the copy Armature vendors, so the server is checked against grpc's)."""
    from grpc_tools import protoc
    out = tempfile.mkdtemp(prefix="reflection-py-")
    if protoc.main(["protoc", f"-I{GRPC_PROTO}", f"--python_out={out}", reflection_proto(version)]) != 0:
        raise RuntimeError("protoc failed")
    # Loaded by path: a "grpc" package on sys.path would shadow grpcio's.
    import importlib.util
    path = os.path.join(out, "grpc", "reflection", version, "reflection_pb2.py")
    spec = importlib.util.spec_from_file_location("reflection_pb2", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main():
    server_bin = sys.argv[1]
    version = sys.argv[2] if len(sys.argv) > 2 else "v1alpha"
    if not os.path.exists(reflection_proto(version)):
        print(f"SKIP: grpc-proto's {version} reflection.proto is not installed")
        return 0
    rpb = reflection_module(version)
    failures, passes = [], []

    def check(cond, what):
        print(("ok   " if cond else "FAIL ") + what)
        (passes if cond else failures).append(what)

    with Server(server_bin) as server:
        channel = grpc.insecure_channel(server.target)
        info = channel.stream_stream(
            f"/grpc.reflection.{version}.ServerReflection/ServerReflectionInfo",
            request_serializer=rpb.ServerReflectionRequest.SerializeToString,
            response_deserializer=rpb.ServerReflectionResponse.FromString)

        def ask(**kw):
            return list(info(iter([rpb.ServerReflectionRequest(**kw)])))[0]

        services = [s.name for s in ask(list_services="").list_services_response.service]
        print("services:", services)
        for s in ("armature.v1.AssetService", "armature.v1.PoseService", "grpc.health.v1.Health",
                  "grpc.reflection.v1.ServerReflection", "grpc.reflection.v1alpha.ServerReflection"):
            check(s in services, f"reflection lists {s}")
        check(len(services) == len(set(services)), "no service is listed twice")
        if version != "v1alpha":
            # gRPC's own v1alpha plugin is the reference for what the server offers.
            apb = reflection_module("v1alpha")
            alpha = channel.stream_stream("/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
                                          request_serializer=apb.ServerReflectionRequest.SerializeToString,
                                          response_deserializer=apb.ServerReflectionResponse.FromString)
            reply = list(alpha(iter([apb.ServerReflectionRequest(list_services="")])))[0]
            alpha_services = sorted(s.name for s in reply.list_services_response.service)
            check(sorted(services) == alpha_services,
                  f"{version} lists the same services as v1alpha ({len(alpha_services)})")
            armature = [s for s in alpha_services if s.startswith("armature.v1.")]
            check(len(armature) >= 4 and all(s in services for s in armature),
                  f"every armature.v1 service is listed ({len(armature)})")

        # Errors come back in error_response, NOT_FOUND naming what was asked.
        for kw, name in ((dict(file_containing_symbol="armature.v1.NoSuchService"), "armature.v1.NoSuchService"),
                         (dict(file_by_filename="armature/v1/no_such.proto"), "armature/v1/no_such.proto"),
                         (dict(all_extension_numbers_of_type="armature.v1.NoSuchMessage"), "armature.v1.NoSuchMessage")):
            err = ask(**kw).error_response
            check(err.error_code == grpc.StatusCode.NOT_FOUND.value[0],
                  f"{list(kw)[0]} of an unknown name is NOT_FOUND ({err.error_code}: {err.error_message})")
            if version != "v1alpha":
                check(name in err.error_message, f"the error names '{name}'")
        ext = ask(file_containing_extension=rpb.ExtensionRequest(
            containing_type="google.protobuf.MethodOptions", extension_number=HTTP_RULE_EXTENSION))
        names = [descriptor_pb2.FileDescriptorProto.FromString(raw).name
                 for raw in ext.file_descriptor_response.file_descriptor_proto]
        check(names[:1] == ["google/api/annotations.proto"],
              f"file_containing_extension finds google.api.http in google/api/annotations.proto ({names})")
        numbers = ask(all_extension_numbers_of_type="google.protobuf.MethodOptions").all_extension_numbers_response
        check(numbers.base_type_name == "google.protobuf.MethodOptions" and
              HTTP_RULE_EXTENSION in numbers.extension_number,
              f"all_extension_numbers_of_type lists {HTTP_RULE_EXTENSION} ({list(numbers.extension_number)})")
        missing = ask(file_containing_extension=rpb.ExtensionRequest(
            containing_type="google.protobuf.MethodOptions", extension_number=12345)).error_response
        check(missing.error_code == grpc.StatusCode.NOT_FOUND.value[0],
              f"an unknown extension number is NOT_FOUND ({missing.error_message})")

        # Fetch the files defining PoseService (and what they import) into a pool.
        pool = descriptor_pool.DescriptorPool()
        pending = [f for f in ask(file_containing_symbol="armature.v1.PoseService")
                   .file_descriptor_response.file_descriptor_proto]
        first = descriptor_pb2.FileDescriptorProto.FromString(pending[0]) if pending else None
        check(first is not None and first.package == "armature.v1" and
              "PoseService" in [sv.name for sv in first.service],
              f"file_containing_symbol PoseService answers a file declaring it ({first.name if first else None})")
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
