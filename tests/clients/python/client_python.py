"""Runs a client test in the interpreter the package is installed in.

The tests take that interpreter (python_client.install_offline's venv) as
their first argument; ctest starts them with the system python3, so each
runs itself again in the venv before importing armature_client.
"""
import os
import sys


def run_in_client_python():
    if os.environ.get("ARMATURE_CLIENT_TEST_PYTHON") == sys.argv[1]:
        return
    if not os.path.exists(sys.argv[1]):
        sys.exit(f"FAIL: {sys.argv[1]} is missing (python_client.install_offline makes it)")
    os.environ["ARMATURE_CLIENT_TEST_PYTHON"] = sys.argv[1]
    os.execv(sys.argv[1], [sys.argv[1], *sys.argv])
