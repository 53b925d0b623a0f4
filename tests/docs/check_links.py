"""Every relative link in README.md, ARCHITECTURE.md and docs/*.md reaches a
file of the repository, and every #anchor a heading of its page (GitHub's
anchor rule: lower case, punctuation dropped, spaces to hyphens). And no page
keeps a template placeholder such as BUILD_MINUTES: an upper-case word with an
underscore in prose (outside code), other than a gRPC status code.

usage: check_links.py REPO_ROOT
"""
import os
import re
import sys

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#{1,6}\s+(.*)$")
PLACEHOLDER = re.compile(r"\b[A-Z][A-Z0-9]*_[A-Z0-9_]*[A-Z0-9]\b")
STATUS_CODES = {"INVALID_ARGUMENT", "DEADLINE_EXCEEDED", "NOT_FOUND", "ALREADY_EXISTS", "PERMISSION_DENIED",
                "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION", "OUT_OF_RANGE", "DATA_LOSS"}


def placeholders(path):
    """(line, word) of each upper-case word with an underscore left in prose."""
    text = open(path, encoding="utf-8").read()
    # Fenced blocks and inline code (which may span lines) become blanks, lines kept.
    text = re.sub(r"^```.*?^```", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text, flags=re.S | re.M)
    text = re.sub(r"`[^`]*`", lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)
    return [(n, w) for n, line in enumerate(text.split("\n"), 1)
            for w in PLACEHOLDER.findall(line) if w not in STATUS_CODES]


def anchors(path):
    found, in_code = set(), False
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            in_code = not in_code
        m = None if in_code else HEADING.match(line)
        if m:
            text = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower().replace("`", ""))
            found.add(text.replace(" ", "-"))
    return found


def main():
    root = os.path.abspath(sys.argv[1])
    pages = ["README.md", "ARCHITECTURE.md"] + [
        os.path.join("docs", f) for f in sorted(os.listdir(os.path.join(root, "docs"))) if f.endswith(".md")]
    problems, checked = [], 0
    for page in pages:
        path = os.path.join(root, page)
        in_code = False
        for number, line in enumerate(open(path, encoding="utf-8"), 1):
            if line.startswith("```"):
                in_code = not in_code
            if in_code:
                continue
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target):  # http:, https:, mailto:
                    continue
                checked += 1
                file_part, _, anchor = target.partition("#")
                dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
                if not os.path.exists(dest):
                    problems.append(f"{page}:{number}: {target}: no such file")
                elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                    problems.append(f"{page}:{number}: {target}: no heading #{anchor}")
        for number, word in placeholders(path):
            problems.append(f"{page}:{number}: {word}: a template placeholder left in the text")
    for p in problems:
        print("FAIL:", p)
    print(f"{checked} links checked in {len(pages)} pages, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
