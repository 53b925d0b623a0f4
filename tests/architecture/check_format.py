"""The C++ sources follow .clang-format: clang-format --dry-run on each,
listing the files it would change (fix: clang-format -i FILE).

usage: check_format.py REPO_ROOT [CLANG_FORMAT]   (make format rewrites them)
"""
import os
import shutil
import subprocess
import sys

ROOTS = ["base", "engine", "server", "clients/cpp", "bench", "tests"]
SKIP_DIRS = {"node_modules", "build", "third_party", "corpus", "regressions", "seeds"}


def sources(root):
    for top in ROOTS:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("."))
            for f in sorted(files):
                if f.endswith((".cc", ".h", ".cpp")):
                    yield os.path.join(folder, f)


def main(root, tool):
    if shutil.which(tool) is None:
        print(f"check_format: {tool} not found (scripts/setup.sh test installs it)")
        return 1
    files = list(sources(root))
    bad = []
    for i in range(0, len(files), 100):
        batch = files[i:i + 100]
        run = subprocess.run([tool, "--dry-run", "--style=file"] + batch, capture_output=True, text=True)
        for line in run.stderr.splitlines():
            if ": warning:" in line or ": error:" in line:
                path = line.split(":", 1)[0]
                if path not in bad:
                    bad.append(path)
    for path in bad:
        print(f"{os.path.relpath(path, root)}: not as .clang-format has it (clang-format -i {os.path.relpath(path, root)})")
    print(f"check_format: {len(files)} files, {len(bad)} to format")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else ".", sys.argv[2] if len(sys.argv) > 2 else "clang-format-14"))
