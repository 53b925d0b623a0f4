"""`pip install ./clients/python` works offline, generates the stubs at build
time, and the installed package (not the source tree) imports and calls a real
armature-server. Two ways, both with --no-index so nothing can be downloaded:
  1. README's: a venv with --system-site-packages (Debian's grpcio, protobuf,
     numpy), then `pip install ./clients/python`;
  2. /usr/bin/python3 -m pip install --no-build-isolation --no-deps --target DIR.
The venv is left in WORK_DIR/venv for python_client.api (a ctest fixture).

usage: install_offline.py SERVER_BIN PACKAGE_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "reference"))
from server_fixture import Server  # noqa: E402

# Runs in the installed package's interpreter, from a folder with no armature_client in it.
PROBE = r"""
import sys
import armature_client
from armature_client import Client, NotFound
expected_root = sys.argv[2]
assert armature_client.__file__.startswith(expected_root), (armature_client.__file__, expected_root)
c = Client(sys.argv[1], token=None, timeout=30)
names = [a.name for a in c.list_assets()]
assert "demo_walk" in names, names
p = c.evaluate_clip("demo_walk", [0.0, 0.5], space="world")
assert p.translations.shape == (2, len(p.joint_names), 3) and p.rotations.shape == (2, len(p.joint_names), 4)
try:
    c.evaluate_clip("no_such_clip", [0.0])
    raise SystemExit("no error for an unknown clip")
except NotFound as e:
    assert "no_such_clip" in e.message, e.message
print("installed at", armature_client.__file__, "assets", names, "joints", len(p.joint_names))
"""


def run(cmd, **kw):
    print("$", " ".join(cmd), flush=True)
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)
    print(r.stdout[-4000:], flush=True)
    if r.returncode != 0:
        raise SystemExit(f"FAIL: exit {r.returncode}: {' '.join(cmd)}")
    return r.stdout


def main():
    server_bin, package_dir, work = sys.argv[1:4]
    for tool in ("protoc", "grpc_python_plugin"):
        if not shutil.which(tool):
            print(f"SKIP: {tool} is not installed (scripts/setup.sh installs it)")
            return 0
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    offline = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    offline.pop("PYTHONPATH", None)

    existed_before = set(os.listdir(package_dir))
    venv = os.path.join(work, "venv")
    run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv])
    venv_python = os.path.join(venv, "bin", "python")
    run([venv_python, "-m", "pip", "install", "--no-index", package_dir], env=offline, cwd=work)

    target = os.path.join(work, "target")
    run(["/usr/bin/python3", "-m", "pip", "install", "--no-index", "--no-build-isolation", "--no-deps",
         "--target", target, package_dir], env=offline, cwd=work)
    generated = os.path.join(target, "armature_client", "_proto", "armature", "v1", "poses_pb2_grpc.py")
    if not os.path.isfile(generated):
        raise SystemExit(f"FAIL: the build generated no stubs ({generated} is missing)")
    in_source = os.path.join(package_dir, "armature_client", "_proto")
    if os.path.exists(in_source):
        raise SystemExit(f"FAIL: the build wrote generated stubs into the source tree ({in_source})")

    # setuptools builds in the tree (.gitignore'd); leave it as it was.
    for leftover in ("build", "armature_client.egg-info"):
        if leftover not in existed_before:
            shutil.rmtree(os.path.join(package_dir, leftover), ignore_errors=True)

    probe = os.path.join(work, "probe.py")
    with open(probe, "w") as f:
        f.write(PROBE)
    with Server(server_bin) as server:
        run([venv_python, probe, server.target, venv], env=offline, cwd=work)
        run(["/usr/bin/python3", probe, server.target, target], env=dict(offline, PYTHONPATH=target), cwd=work)
    print("ok: installed offline (venv and --target), imported from the install, called the server")
    return 0


if __name__ == "__main__":
    sys.exit(main())
