"""armature-client: the Python client of the Armature animation server.

The gRPC stubs are not in the source tree: build_py generates them from the
repository's proto/ with Debian's protoc and grpc_python_plugin
(protobuf-compiler, protobuf-compiler-grpc), so the package always matches the
API it is built with. Install offline with

    python3 -m venv --system-site-packages .venv && .venv/bin/pip install ./clients/python

(Debian's pip 23 builds it with the installed setuptools; a newer pip needs
--no-build-isolation to stay offline.)
"""
import os
import sys

from setuptools import setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from generate_stubs import generate  # noqa: E402


class BuildPyWithStubs(build_py):
    """build_py that first writes armature_client/_proto/ into the build directory."""

    def run(self):
        super().run()
        if not self.dry_run:
            generate(os.path.join(self.build_lib, "armature_client", "_proto"))


setup(
    name="armature-client",
    version="0.1.0",
    description="Python client of the Armature animation server (gRPC, numpy arrays)",
    packages=["armature_client"],
    python_requires=">=3.9",
    # Debian: python3-grpcio, python3-protobuf, python3-numpy.
    install_requires=["grpcio", "protobuf", "numpy"],
    cmdclass={"build_py": BuildPyWithStubs},
)
