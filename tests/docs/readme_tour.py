"""Runs the README's tour against a real armature-server, as a newcomer would.

Every command in the ```sh blocks between <!-- tour:begin --> and
<!-- tour:end --> runs, in order, in one bash shell (so `export` and
variables carry over) inside a fresh directory, against a server on free
ports with a fresh data directory (the demo assets seeded, as on a fresh
`make run`). A failing command fails the test, naming its README line and
the command. Substituted so the commands reach that server: localhost:8080
and localhost:50051 become its ports, $PWD/build/bin the built binaries'
folder, ARMATURE_SERVER its gRPC address; `curl` gets --fail-with-body -sS
so an HTTP error fails the step.

A command right after a `# tour: needs <feature>` line is skipped and
reported: the tour shows it as it will work once <feature> lands; remove the
marker then.

usage: readme_tour.py SERVER_BIN BIN_DIR README [--no-server]
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reference"))
from server_fixture import Server  # noqa: E402

BEGIN, END = "<!-- tour:begin -->", "<!-- tour:end -->"
NEEDS = re.compile(r"^#\s*tour:\s*needs\s+(\S+)")
STEP_TIMEOUT_SECONDS = 240


class Step:
    def __init__(self, line, text, needs=None):
        self.line, self.text, self.needs = line, text, needs


def balanced(text):
    try:
        shlex.split(text, comments=True)
        return True
    except ValueError:  # an open quote: the command goes on
        return False


def tour_steps(readme_text):
    """The tour's commands with their README line numbers."""
    lines = readme_text.split("\n")
    try:
        begin = next(i for i, l in enumerate(lines) if l.strip() == BEGIN)
        end = next(i for i, l in enumerate(lines) if l.strip() == END and i > begin)
    except StopIteration:
        raise SystemExit(f"FAIL: README has no {BEGIN} … {END} section")
    steps, in_block, needs, i = [], False, None, begin + 1
    while i < end:
        line = lines[i]
        if line.strip().startswith("```"):
            in_block = not in_block and line.strip() == "```sh"
            i += 1
            continue
        if not in_block or not line.strip():
            i += 1
            continue
        if line.lstrip().startswith("#"):
            m = NEEDS.match(line.strip())
            if m:
                needs = m.group(1)
            i += 1
            continue
        start, text = i, line
        while text.endswith("\\") or not balanced(text):
            i += 1
            if i >= end:
                raise SystemExit(f"FAIL: README line {start + 1}: the command never ends: {text}")
            text += "\n" + lines[i]
        steps.append(Step(start + 1, text, needs))
        needs = None
        i += 1
    if not steps:
        raise SystemExit("FAIL: the README's tour has no ```sh commands")
    return steps


def substitute(text, grpc_port, http_port, bin_dir):
    text = text.replace("localhost:8080", f"127.0.0.1:{http_port}")
    text = text.replace("localhost:50051", f"127.0.0.1:{grpc_port}")
    text = text.replace("$PWD/build/bin", bin_dir)
    return re.sub(r"(^|[|;&(]\s*)curl ", r"\1curl --fail-with-body -sS ", text)


SCRIPT_HEAD = r"""set -o pipefail
__tour_step() {
  local __tour_line=$1 __tour_cmd
  __tour_cmd=$(cat)
  printf '\n### README line %s\n$ %s\n' "$__tour_line" "$__tour_cmd"
  eval "$__tour_cmd"
  local __tour_rc=$?
  if [ "$__tour_rc" -ne 0 ]; then
    printf '\nFAIL: README line %s exited with %s: %s\n' "$__tour_line" "$__tour_rc" "$__tour_cmd"
    exit 1
  fi
}
"""


def run(steps, env, workdir, grpc_port, http_port, bin_dir):
    script = SCRIPT_HEAD
    ran = []
    for s in steps:
        if s.needs:
            print(f"SKIP: README line {s.line} needs {s.needs}: {s.text}")
            continue
        body = substitute(s.text, grpc_port, http_port, bin_dir)
        script += f"__tour_step {s.line} <<'__TOUR_COMMAND__'\n{body}\n__TOUR_COMMAND__\n"
        ran.append(s)
    try:
        r = subprocess.run(["bash", "-c", script], cwd=workdir, env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True, timeout=STEP_TIMEOUT_SECONDS)
        sys.stdout.write(r.stdout)
        return r.returncode, ran
    except subprocess.TimeoutExpired as e:
        out = e.stdout if isinstance(e.stdout, str) else (e.stdout or b"").decode()
        sys.stdout.write(out)
        started = re.findall(r"### README line (\d+)", out)
        where = f"README line {started[-1]}" if started else "the first command"
        print(f"\nFAIL: {where} did not finish within {STEP_TIMEOUT_SECONDS} s")
        return 1, ran


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) != 3:
        raise SystemExit(__doc__)
    server_bin, bin_dir, readme = args
    steps = tour_steps(open(readme, encoding="utf-8").read())
    with tempfile.TemporaryDirectory(prefix="armature-tour-") as workdir, \
            tempfile.TemporaryDirectory(prefix="armature-tour-tmp-") as tmp:
        # TMPDIR: the tour's own scratch folders (mktemp) are removed with the test's.
        env = dict(os.environ, PATH=bin_dir + os.pathsep + os.environ.get("PATH", ""), TMPDIR=tmp)
        for k in ("ARMATURE_TOKEN", "ARMATURE_CA_FILE"):
            env.pop(k, None)
        if "--no-server" in sys.argv:  # the runner's own test: no server needed
            code, ran = run(steps, env, workdir, 50051, 8080, bin_dir)
        else:
            with Server(server_bin) as server:
                env["ARMATURE_SERVER"] = server.target
                code, ran = run(steps, env, workdir, server.grpc_port, server.http_port, bin_dir)
                if code != 0:
                    print("\nserver log:\n" + server.read_log()[-4000:])
        # The tour starts in the repository's folder: what it writes there, a user finds in `git status`.
        left = sorted(os.listdir(workdir))
        if code == 0 and left:
            print(f"\nFAIL: the tour leaves {len(left)} files in the folder it starts in: {', '.join(left)}")
            code = 1
    skipped = [s for s in steps if s.needs]
    print(f"\nreadme tour: {len(steps)} commands, {len(skipped)} skipped"
          + (" (needs: " + ", ".join(sorted({s.needs for s in skipped})) + ")" if skipped else "")
          + (f"; the {len(ran)} others passed" if code == 0 else "; FAILED"))
    return code


if __name__ == "__main__":
    sys.exit(main())
