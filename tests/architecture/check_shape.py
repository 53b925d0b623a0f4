"""ARCHITECTURE.md's size rules, checked on every source the project writes.

- A folder holds at most MAX_SOURCES sources directly: a source is a .cc, a
  header without a .cc beside it, or a .js/.mjs/.ts module.
- No function (C++ or JavaScript/TypeScript) runs over MAX_FUNCTION_LINES lines,
  its signature included; no file over MAX_FILE_LINES lines.

The function scan blanks comments and string literals, then matches braces: a
brace block whose head has a parameter list, opened outside any other
function, is a function (lambdas and local classes count toward theirs).

usage: check_shape.py REPO_ROOT
"""
import os
import re
import sys

MAX_SOURCES = 15
MAX_FUNCTION_LINES = 100
MAX_FILE_LINES = 600
ROOTS = ["base", "engine", "server", "clients", "web/src", "web/test", "bench", "tests"]
SKIP_DIRS = {"node_modules", "build", "gen", "dist", "__pycache__", "third_party", "corpus", "regressions", "seeds"}
CPP = (".cc", ".h", ".cpp")
JS = (".js", ".mjs", ".ts")


def blank(text, js):
    """The text with comments and string literals blanked, newlines kept."""
    out, i, n = [], 0, len(text)
    quotes = "\"'`" if js else "\"'"
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
        elif not js and text.startswith('R"', i) and (i == 0 or not text[i - 1].isalnum()):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if not m:
                out.append(text[i])
                i += 1
                continue
            j = text.find(")" + m.group(1) + '"', i)
            j = n if j < 0 else j + len(m.group(1)) + 2
        elif text[i] in quotes and not (text[i] == "'" and not js and i > 0 and text[i - 1].isalnum()):
            q, j = text[i], i + 1
            while j < n and text[j] != q and (q == "`" or text[j] != "\n"):
                j += 2 if text[j] == "\\" else 1
            j += 1
        else:
            out.append(text[i])
            i += 1
            continue
        out.append(re.sub(r"[^\n]", " ", text[i:j]))
        i = j
    return "".join(out)


NOT_A_FUNCTION = re.compile(r"\b(namespace|class|struct|enum|union|extern)\b[^()]*$|=\s*$|\b(if|for|while|switch|catch)\s*\(.*\)\s*$")


def functions(path):
    """(lines, first line, head) of each outermost function in a file."""
    js = path.endswith(JS)
    text = blank(open(path, encoding="utf-8", errors="replace").read(), js)
    stack, found, last = [], [], 0
    for i, c in enumerate(text):
        if c == "{":
            head = text[last:i]
            inside = any(kind == "function" for kind, _ in stack)
            is_function = not inside and ")" in head and not NOT_A_FUNCTION.search(head.strip())
            if js and not inside and re.search(r"=>\s*$", head):
                is_function = True
            start = last + len(head) - len(head.lstrip())
            stack.append(("function" if is_function else "block", start))
            last = i + 1
        elif c == "}":
            if stack:
                kind, start = stack.pop()
                if kind == "function":
                    first = text.count("\n", 0, start) + 1
                    found.append((text.count("\n", 0, i) + 2 - first, first, " ".join(text[start:start + 90].split())))
            last = i + 1
        elif c == ";" or (js and c == "," and not stack):
            last = i + 1
    return found


def main(root):
    problems = []
    for top in ROOTS:
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs[:] = sorted(d for d in dirs if d not in SKIP_DIRS and not d.startswith("."))
            rel = os.path.relpath(folder, root)
            stems = {os.path.splitext(f)[0] for f in files if f.endswith(".cc")}
            sources = [f for f in files if f.endswith((".cc",) + JS) or
                       (f.endswith(".h") and os.path.splitext(f)[0] not in stems)]
            if len(sources) > MAX_SOURCES:
                problems.append(f"{rel}/: {len(sources)} sources (at most {MAX_SOURCES}): split it by concern")
            for f in sorted(files):
                if not f.endswith(CPP + JS) or f.endswith((".min.js", ".d.ts")) or "_pb" in f:
                    continue
                path = os.path.join(folder, f)
                lines = open(path, encoding="utf-8", errors="replace").read().count("\n")
                if lines > MAX_FILE_LINES:
                    problems.append(f"{rel}/{f}: {lines} lines (at most {MAX_FILE_LINES})")
                for length, first, head in functions(path):
                    if length > MAX_FUNCTION_LINES:
                        problems.append(f"{rel}/{f}:{first}: a function of {length} lines "
                                        f"(at most {MAX_FUNCTION_LINES}): {head}")
    for p in problems:
        print(p)
    print(f"check_shape: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "."))
