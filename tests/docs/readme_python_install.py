"""The README's Python client steps, literally, as a newcomer runs them.

The ```sh block of the README's **Python** item runs, line by line, in a
clean folder holding a copy of clients/python and proto/ (the repository's
layout, so `./clients/python` is the README's own path), with no package
index (PIP_NO_INDEX, no find-links): what the Debian packages and the package
itself hold is all there is. The shell's PATH is the caller's, so a pyenv
`python3` ahead of Debian's is met as a user meets it. Then the README's
```python example runs in that venv against a real armature-server, and the
Debian packages the item names must be among those `make run` installs
(scripts/setup.sh with SETUP_LIST=1).

usage: readme_python_install.py SERVER_BIN REPO_DIR
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import textwrap

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reference"))
from server_fixture import Server  # noqa: E402

MARKER = "- **Python**"


def python_item(readme_text):
    """The README's Python item: from its bullet to the next bullet."""
    start = readme_text.index(MARKER)
    end = readme_text.index("\n- **", start + len(MARKER))
    return readme_text[start:end]


def fenced(item, language):
    start = item.index("```" + language) + len("```" + language)
    return textwrap.dedent(item[start:item.index("```", start)]).strip("\n")


def run(cmd, cwd, env, what):
    print(f"$ {cmd}", flush=True)
    r = subprocess.run(["bash", "-c", cmd], cwd=cwd, env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=240)
    print(r.stdout[-4000:], flush=True)
    if r.returncode != 0:
        raise SystemExit(f"FAIL: {what} exited with {r.returncode}: {cmd}")
    return r.stdout


def check_setup_installs(item, repo):
    named = set(re.findall(r"`(python3-[\w.+-]+)`", item))
    if not named:
        raise SystemExit("FAIL: the README's Python item names no Debian package")
    listed = subprocess.run(["bash", os.path.join(repo, "scripts", "setup.sh")], env=dict(os.environ, SETUP_LIST="1"),
                            stdout=subprocess.PIPE, text=True, check=True).stdout.split()
    missing = sorted(named - set(listed))
    if missing:
        raise SystemExit(f"FAIL: the README names {missing}, which `make run` (scripts/setup.sh) does not install")
    print("make run installs", sorted(named))


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    server_bin, repo = sys.argv[1:3]
    for tool in ("protoc", "grpc_python_plugin"):
        if not shutil.which(tool):
            print(f"SKIP: {tool} is not installed (scripts/setup.sh installs it)")
            return 0
    item = python_item(open(os.path.join(repo, "README.md"), encoding="utf-8").read())
    check_setup_installs(item, repo)
    install, example = fenced(item, "sh"), fenced(item, "python")

    env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    for k in ("PIP_FIND_LINKS", "PIP_INDEX_URL", "PIP_EXTRA_INDEX_URL", "PYTHONPATH", "VIRTUAL_ENV"):
        env.pop(k, None)
    skip = shutil.ignore_patterns("build", "*.egg-info", "__pycache__", "_proto")
    with tempfile.TemporaryDirectory(prefix="armature-readme-python-") as work:
        shutil.copytree(os.path.join(repo, "clients", "python"), os.path.join(work, "clients", "python"), ignore=skip)
        shutil.copytree(os.path.join(repo, "proto"), os.path.join(work, "proto"))
        for line in install.splitlines():
            if line.strip() and not line.lstrip().startswith("#"):
                run(line, work, env, "the README's install step")

        probe = os.path.join(work, "readme_example.py")
        with open(probe, "w") as f:
            f.write(example + "\nprint(body.shape)\n")
        with Server(server_bin) as server:
            with open(probe) as f:
                text = f.read().replace("localhost:50051", server.target)
            with open(probe, "w") as f:
                f.write(text)
            out = run(f".venv/bin/python {probe}", work, env, "the README's example").split()
    # "Hips (2, J, 3) (2, J, 4) (V, 3)": both arrays over the same joints, the body's vertices in 3-D.
    joints = out[2].rstrip(",")
    expected = ["Hips", "(2,", f"{joints},", "3)", "(2,", f"{joints},", "4)"]
    if out[:7] != expected or int(joints) < 2 or out[-1] != "3)":
        raise SystemExit(f"FAIL: the example printed {out}, expected {expected} then (vertices, 3)")
    print(f"ok: the README's install ran offline and its example printed {' '.join(out)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
