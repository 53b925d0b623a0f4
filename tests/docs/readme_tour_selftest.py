"""The tour runner's own test: on a tour whose third command fails it exits
non-zero naming that command and its README line, skips the command marked
`# tour: needs`, carries variables and continued lines over, and runs
nothing outside the markers or after the failure."""
import os
import subprocess
import sys

here = os.path.dirname(os.path.abspath(__file__))
r = subprocess.run([sys.executable, os.path.join(here, "readme_tour.py"), "unused", "/usr/bin",
                    os.path.join(here, "fixtures", "failing_tour.md"), "--no-server"],
                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
out = r.stdout
print(out)
checks = [
    ("exit code 1", r.returncode == 1),
    ("names the failing command and its line", "FAIL: README line 15 exited with 3: sh -c 'exit 3'" in out),
    ("skips the marked command", "SKIP: README line 14 needs time-travel: exit 7" in out),
    ("variables and continued lines carry over", "\ncontinued line\n" in out),
    ("nothing after the failure runs", "never reached\n" not in out.replace("$ echo never reached", "")),
    ("nothing outside the markers runs", "outside the tour" not in out),
    ("the summary", "readme tour: 5 commands, 1 skipped (needs: time-travel); FAILED" in out),
]
failed = [what for what, ok in checks if not ok]
for what in failed:
    print("FAIL:", what)
sys.exit(1 if failed else 0)
