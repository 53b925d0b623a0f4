"""Generates armature_client/_proto/ from the repository's .proto files.

protoc writes modules that import each other as top-level packages
(`from armature.v1 import types_pb2`, `from google.api import annotations_pb2`);
they are rewritten to live under `armature_client._proto`, so they never clash
with another package's `google.api` (googleapis-common-protos).

usage: python3 generate_stubs.py OUT_DIR   (also called by setup.py)
Environment: ARMATURE_PROTO_DIR (default: ../../proto from here), PROTOC,
GRPC_PYTHON_PLUGIN (default: found on PATH).
"""
import glob
import os
import re
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE = "armature_client._proto"
# Top-level packages protoc's modules import, rewritten under PACKAGE.
ROOTS = ("armature", "google.api")


def _tool(env, name, package):
    path = os.environ.get(env) or shutil.which(name)
    if not path:
        raise RuntimeError(f"armature-client: '{name}' not found (Debian: apt-get install {package}); "
                           f"or set {env}")
    return path


def proto_files(proto_dir):
    files = sorted(glob.glob(os.path.join(proto_dir, "armature", "v1", "*.proto")))
    if not files:
        raise RuntimeError(f"armature-client: no armature/v1/*.proto under {proto_dir}; "
                           "set ARMATURE_PROTO_DIR to the repository's proto/ folder")
    files += [os.path.join(proto_dir, "google", "api", n) for n in ("annotations.proto", "http.proto")]
    return [os.path.relpath(f, proto_dir) for f in files]


def _rewrite_imports(path):
    with open(path) as f:
        text = f.read()
    for root in ROOTS:
        text = re.sub(rf"^from {re.escape(root)}(\.| import)", rf"from {PACKAGE}.{root}\1", text, flags=re.M)
    with open(path, "w") as f:
        f.write(text)


def generate(out_dir, proto_dir=None):
    proto_dir = os.path.abspath(proto_dir or os.environ.get("ARMATURE_PROTO_DIR")
                                or os.path.join(HERE, "..", "..", "proto"))
    protoc = _tool("PROTOC", "protoc", "protobuf-compiler")
    plugin = _tool("GRPC_PYTHON_PLUGIN", "grpc_python_plugin", "protobuf-compiler-grpc")
    files = proto_files(proto_dir)
    if os.path.isdir(out_dir):
        shutil.rmtree(out_dir)
    os.makedirs(out_dir)
    subprocess.run([protoc, f"--plugin=protoc-gen-grpc_python={plugin}", f"-I{proto_dir}",
                    f"--python_out={out_dir}", f"--grpc_python_out={out_dir}", *files], check=True)
    for dirpath, _, names in os.walk(out_dir):
        open(os.path.join(dirpath, "__init__.py"), "a").close()
        for n in names:
            if n.endswith(".py"):
                _rewrite_imports(os.path.join(dirpath, n))
    return out_dir


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    print(generate(sys.argv[1]))
