#!/usr/bin/env python3
"""Reorganise the Armature repository into folders by concern (re-runnable migration).

  relayout.py REPO            git mv every file per MOVES, rewrite includes and path
                              references, install the hand-written files, then --check.
  relayout.py --check REPO    verify an already migrated tree (folder sizes, header/source
                              folders, folder include cycles, layering rules).
  relayout.py --table         print the move table (Markdown) to stdout.

It fails loudly (exit 1, before touching anything) when a C++ file under engine/, server/
or tests/ is neither in the table nor covered by a fallback rule. CMakeLists that the
script replaces are 3-way merged (git merge-file) against the version they were written
from (BASE_COMMIT), so edits made on main meanwhile are kept or reported as conflicts.
Leaves the changes staged; commit them yourself.
"""
import argparse
import os
import posixpath
import re
import shutil
import subprocess
import sys
from collections import defaultdict

HERE = os.path.dirname(os.path.abspath(__file__))
FILES = os.path.join(HERE, "files")

CPP_EXT = (".cc", ".h", ".inc", ".cpp", ".hpp")

# ---------------------------------------------------------------- the table
ENGINE = {  # concern: (public headers, src files)
    "math": (["rotation.h", "transform.h"], ["rotation.cc"]),
    "anim": (["skeleton.h", "clip.h"], ["skeleton.cc", "clip.cc"]),
    "io": (["asset.h", "import_limits.h", "bvh.h", "gltf.h", "obj.h", "demo_character.h", "demo_walk.h"],
           ["asset.cc", "bvh_reader.cc", "bvh_writer.cc", "gltf_accessor.cc", "gltf_accessor.h",
            "gltf_import.cc", "obj_import.cc", "demo_character.cc", "demo_walk.cc"]),
    "kinematics": (["fk.h", "ik.h", "ik_aim.h", "ik_ccd.h", "ik_dls.h", "ik_fabrik.h", "ik_limits.h",
                    "ik_two_bone.h", "ik_types.h", "ik_workspace.h"],
                   ["fk.cc", "ik.cc", "ik_aim.cc", "ik_ccd.cc", "ik_common.cc", "ik_dls.cc", "ik_fabrik.cc",
                    "ik_internal.h", "ik_limits.cc", "ik_two_bone.cc", "ik_workspace.cc"]),
    # deform.{h,cc} is the morph-then-skin vertex pipeline (skinning, blendshapes), not ARAP.
    "mesh": (["mesh.h", "mesh_topology.h", "skinning.h", "blendshape.h", "auto_weights.h"],
             ["mesh.cc", "mesh_topology.cc", "skinning.cc", "skinning_kernels.cc", "skinning_kernels.h",
              "skinning_kernels.inc", "skinning_kernels_avx2.cc", "blendshape.cc", "auto_weights.cc",
              "deform.cc", "deform.h"]),
    "deform": (["arap.h", "deformation_constraints.h", "laplacian_editor.h", "laplacian_operator.h"],
               ["arap.cc", "deformation_system.cc", "deformation_system.h", "laplacian_editor.cc",
                "laplacian_operator.cc"]),
    "parallel": ([], ["worker_pool.cc", "worker_pool.h"]),
}
BASE_HEADERS = ["status.h"]  # engine/include/armature/engine/X -> base/include/armature/base/X

SERVER = {  # folder: files (server/X -> server/folder/X)
    "rpc": ["grpc_status.cc", "grpc_status.h", "proto_convert.cc", "proto_convert.h",
            "request_validation.cc", "request_validation.h", "limits.h", "metrics.cc", "metrics.h",
            "session_admission.cc", "session_admission.h", "frame_scheduler.cc", "frame_scheduler.h",
            "paced_stream_reactor.h", "stream_pacing.h", "elastic_thread_pool.cc", "elastic_thread_pool.h",
            "call_guard.cc", "call_guard.h", "admission_ticket.h", "stream_admission.cc", "stream_admission.h"],
    "assets": ["asset_service.cc", "asset_service.h", "import_reactor.cc", "import_reactor.h",
               "asset_store.cc", "asset_store.h", "mesh_info.cc", "asset_memory.cc", "asset_memory.h",
               "asset_limits.cc", "asset_limits.h", "data_dir_lock.cc", "data_dir_lock.h",
               "file_io.cc", "file_io.h", "demo_assets.cc", "demo_assets.h"],
    "pose": ["pose_service.cc", "pose_service.h", "stream_clip_reactor.cc", "stream_clip_reactor.h"],
    "mesh": ["mesh_service.cc", "mesh_service.h"],
    "ik": ["ik_service.cc", "ik_service.h", "ik_session_reactor.cc", "ik_session_reactor.h",
           "ik_convert.cc", "ik_convert.h"],
    "deform": ["deform_service.cc", "deform_service.h", "mesh_deformer.cc", "mesh_deformer.h",
               "deformer_cache.cc", "deformer_cache.h"],
    "host": ["armature_server.cc", "armature_server.h", "services.cc", "services.h", "config.cc", "config.h",
             "http_server.cc", "http_server.h", "auth_gate.cc", "auth_gate.h", "bearer_tokens.cc",
             "bearer_tokens.h", "server_credentials.cc", "server_credentials.h", "rpc_observer.cc",
             "rpc_observer.h", "logging.cc", "logging.h", "metrics_http.cc", "metrics_http.h", "main.cc"],
}
GATEWAY = ["call_registry", "cors", "error_mapping", "field_path", "gateway", "generic_call", "http_rule",
           "json_codec", "openapi", "path_template", "sse", "transcoder"]  # server/gateway -> server/host/gateway

ENGINE_TESTS = {  # tests/engine/X -> tests/engine/concern/X
    "math": ["rotation_test.cc"],
    "anim": ["clip_test.cc"],
    "io": ["bvh_test.cc", "gltf_import_test.cc", "gltf_interpolation_test.cc", "gltf_reference_test.cc",
           "obj_test.cc", "import_totality_test.cc", "demo_character_test.cc", "demo_walk_test.cc", "reference_scripts_test.cc"],
    "kinematics": ["fk_test.cc", "ik_aim_test.cc", "ik_ccd_fabrik_test.cc", "ik_dls_test.cc",
                   "ik_two_bone_test.cc", "ik_validation_test.cc"],
    "mesh": ["skinning_test.cc", "blendshape_test.cc", "auto_weights_test.cc"],
    "deform": ["arap_test.cc", "laplacian_editor_test.cc", "laplacian_operator_test.cc"],
    # Helpers shared across concerns, by the integration tests and by bench/.
    "testing": ["bvh_reference.h", "deformation_test_util.h", "generated_meshes.h", "ik_rigs.h",
                "mesh_test_util.h", "scipy_reference.h", "test_files.h"],
}
INTEGRATION_SUPPORT = ["client_helpers.cc", "client_helpers.h", "server_process.cc", "server_process.h",
                       "http_get.cc", "http_get.h", "metrics_scrape.cc", "metrics_scrape.h",
                       "deform_grid.cc", "deform_grid.h"]


def build_moves():
    m = {}
    for c, (hdrs, srcs) in ENGINE.items():
        for h in hdrs:
            m[f"engine/include/armature/engine/{h}"] = f"engine/include/armature/engine/{c}/{h}"
        for s in srcs:
            m[f"engine/src/{s}"] = f"engine/src/{c}/{s}"
    for h in BASE_HEADERS:
        m[f"engine/include/armature/engine/{h}"] = f"base/include/armature/base/{h}"
    for folder, files in SERVER.items():
        for f in files:
            m[f"server/{f}"] = f"server/{folder}/{f}"
    for g in GATEWAY:
        for ext in (".cc", ".h"):
            m[f"server/gateway/{g}{ext}"] = f"server/host/gateway/{g}{ext}"
    for c, files in ENGINE_TESTS.items():
        for f in files:
            m[f"tests/engine/{f}"] = f"tests/engine/{c}/{f}"
    for f in INTEGRATION_SUPPORT:
        m[f"tests/integration/{f}"] = f"tests/integration/support/{f}"
    m["tests/gateway/gateway_unit_test.cc"] = "tests/server/host/gateway/gateway_unit_test.cc"
    return m


MOVES = build_moves()

# Files installed from files/ (whole file; 3-way merged when main changed them since BASE_COMMIT).
INSTALLED = ["base/CMakeLists.txt", "engine/CMakeLists.txt", "server/CMakeLists.txt",
             "tests/CMakeLists.txt", "ARCHITECTURE.md"]

# ---------------------------------------------------------------- fallback rules for new files
ENGINE_PREFIX = [  # (regex on the basename, concern)
    (r"^(rotation|transform|quaternion)", "math"),
    (r"^(skeleton|clip|sampl|blend_tree|blending)", "anim"),
    (r"^(bvh|gltf|obj|asset|demo_)", "io"),
    (r"^(fk|ik)(_|\.)", "kinematics"),
    (r"^(mesh|skinning|blendshape|auto_weights)", "mesh"),
    (r"^(laplacian|arap|deformation)", "deform"),
    (r"^(worker_pool|thread)", "parallel"),
]
BASE_FILES = r"^(utf8|status|strings?|bytes)(_|\.)"  # small shared helpers -> base/
SERVER_PREFIX = [
    (r"^(pose_|stream_clip)", "pose"),
    (r"^mesh_(service|stream|convert)", "mesh"),
    (r"^ik_", "ik"),
    (r"^(deform|mesh_deformer|factorization)", "deform"),
    (r"^(asset_|import_|upload|data_dir|file_io|demo_assets|mesh_info|manifest|replica)", "assets"),
    (r"^(grpc_status|proto_convert|request_validation|limits|metrics\.|session_admission|frame_sched|"
     r"paced_|stream_pacing|elastic_thread|pose_convert)", "rpc"),
    (r"^(armature_server|services|config|http_server|auth_|bearer|server_credentials|tls|rpc_observer|"
     r"logging|metrics_http|main\.)", "host"),
]
ENGINE_TEST_PREFIX = [(r, c) for r, c in ENGINE_PREFIX] + [(r"^(reference_|.*_reference\.h$|.*_util\.h$)", "testing")]


def fallback(path):
    """New path for a file the table does not name, or None (= unmapped, fail)."""
    d, b = posixpath.split(path)
    if path.startswith("engine/src/") and d == "engine/src":
        if re.match(BASE_FILES, b):  # base has no private headers: a header becomes public
            return f"base/src/{b}" if not b.endswith(".h") else f"base/include/armature/base/{b}"
        for rx, c in ENGINE_PREFIX:
            if re.match(rx, b):
                return f"engine/src/{c}/{b}"
    if d == "engine/include/armature/engine":
        if re.match(BASE_FILES, b):
            return f"base/include/armature/base/{b}"
        for rx, c in ENGINE_PREFIX:
            if re.match(rx, b):
                return f"engine/include/armature/engine/{c}/{b}"
    if d == "server":
        for rx, f in SERVER_PREFIX:
            if re.match(rx, b):
                return f"server/{f}/{b}"
    if d == "server/gateway":
        return f"server/host/gateway/{b}"
    if d == "tests/engine":
        for rx, c in ENGINE_TEST_PREFIX:
            if re.match(rx, b):
                return f"tests/engine/{c}/{b}"
    if d == "tests/gateway":
        return f"tests/server/host/gateway/{b}"
    if d == "tests/integration" and not b.endswith("_test.cc") and re.match(
            r"^(client_|server_process|http_|metrics_scrape|.*_helpers?\.)", b):
        return f"tests/integration/support/{b}"
    # Integration tests, fuzzers and the rest of tests/ stay where they are.
    if path.startswith(("tests/integration/", "tests/fuzz/", "tests/common/", "tests/package/",
                        "tests/reference/", "tests/scripts/")):
        return path
    return None


# ---------------------------------------------------------------- helpers
def git(repo, *args, capture=True):
    r = subprocess.run(["git", "-C", repo, *args], capture_output=capture, text=True)
    if r.returncode != 0:
        sys.exit(f"git {' '.join(args)} failed:\n{r.stderr}")
    return r.stdout


def tracked(repo):
    return [p for p in git(repo, "ls-files", "-z").split("\0") if p]


def is_cpp(p):
    return p.endswith(CPP_EXT)


def die(title, lines):
    print(f"\nRELAYOUT FAILED: {title}", file=sys.stderr)
    for l in lines:
        print(f"  {l}", file=sys.stderr)
    sys.exit(1)


def table_markdown(moves):
    out = ["# Relayout moves", "", "| old path | new path |", "|---|---|"]
    out += [f"| `{o}` | `{n}` |" for o, n in sorted(moves.items(), key=lambda kv: kv[1])]
    return "\n".join(out) + "\n"


INCLUDE_RX = re.compile(r'^(\s*#\s*include\s*)([<"])([^>"]+)([>"])', re.M)
OLD_ROOTS = ["engine/include", "", "client/include"]


def resolve_include(name, quote, includer_old, old_files):
    """Repo path (in the old tree) that an include names, or None (system/generated header)."""
    if quote == '"':
        cand = posixpath.normpath(posixpath.join(posixpath.dirname(includer_old), name))
        if cand in old_files:
            return cand
    for root in OLD_ROOTS:
        cand = posixpath.normpath(posixpath.join(root, name)) if root else posixpath.normpath(name)
        if cand in old_files:
            return cand
    return None


def spell_include(target_new, includer_new):
    """How the includer (at its new path) names the target (at its new path)."""
    for root in ("base/include/", "engine/include/", "client/include/"):
        if target_new.startswith(root):
            return target_new[len(root):]
    if target_new.startswith("engine/src/"):
        if posixpath.dirname(target_new) == posixpath.dirname(includer_new):
            return posixpath.basename(target_new)
        if includer_new.startswith("engine/src/"):
            return target_new[len("engine/src/"):]  # engine/src is a PRIVATE include dir
        return None
    if target_new.startswith("server/"):
        return target_new  # the repo root is the server's include dir
    # tests/, bench/ and the rest: relative to the includer.
    return posixpath.relpath(target_new, posixpath.dirname(includer_new))


def rewrite_includes(text, includer_old, includer_new, old_files, full_map, problems):
    def sub(m):
        pre, q, name, q2 = m.groups()
        target_old = resolve_include(name, q, includer_old, old_files)
        if target_old is None:
            return m.group(0)
        target_new = full_map.get(target_old, target_old)
        spelled = spell_include(target_new, includer_new)
        if spelled is None:
            problems.append(f"{includer_new}: cannot spell include of {target_new}")
            return m.group(0)
        return f"{pre}{q}{spelled}{q2}"
    return INCLUDE_RX.sub(sub, text)


def reference_map(moves):
    """Text replacements for path mentions in docs, CMake, scripts and comments."""
    refs = dict(moves)
    for o, n in moves.items():
        for root in ("engine/include/", "base/include/"):
            if o.startswith("engine/include/"):
                oi = o[len("engine/include/"):]
                ni = n[len(root):] if n.startswith(root) else None
                if ni:
                    refs[oi] = ni
    refs["server/gateway/"] = "server/host/gateway/"
    refs["tests/gateway/"] = "tests/server/host/gateway/"
    return refs


def replace_references(text, refs):
    keys = sorted(refs, key=len, reverse=True)
    rx = re.compile(r"(?<![\w.-])(?<![\w-]/)(" + "|".join(re.escape(k) for k in keys) + r")(?![\w])")
    return rx.sub(lambda m: refs[m.group(1)], text)


TEXT_EXT = (".md", ".txt", ".cmake", ".sh", ".py", ".mjs", ".js", ".yaml", ".yml", ".in", ".json") + CPP_EXT
TEXT_NAMES = ("Makefile", "Dockerfile", ".dockerignore", ".gitignore", "run")
SKIP_TEXT = ("package-lock.json",)


def is_text_target(p):
    b = posixpath.basename(p)
    if b in SKIP_TEXT or "/node_modules/" in p:
        return False
    return p.endswith(TEXT_EXT) or b in TEXT_NAMES


# ---------------------------------------------------------------- migrate
def plan(repo):
    files = tracked(repo)
    old_files = set(files)
    if os.path.isdir(os.path.join(repo, "server/rpc")) or os.path.isdir(os.path.join(repo, "engine/src/math")):
        die("the tree looks migrated already (server/rpc or engine/src/math exists)", [])
    moves, unmapped, missing = {}, [], []
    for o, n in MOVES.items():
        if o in old_files:
            moves[o] = n
        else:
            missing.append(o)
    fell_back = {}
    for p in files:
        if not is_cpp(p) or p in moves or not p.startswith(("engine/", "server/", "tests/")):
            continue
        n = fallback(p)
        if n is None:
            unmapped.append(p)
        elif n != p:
            moves[p] = n
            fell_back[p] = n
    if unmapped:
        die("files the mapping does not cover (add them to MOVES in relayout.py):", sorted(unmapped))
    clash = defaultdict(list)
    for o, n in moves.items():
        clash[n].append(o)
    dup = [f"{n} <- {os_}" for n, os_ in clash.items() if len(os_) > 1 or (n in old_files and n not in moves)]
    if dup:
        die("two files would land on the same path:", dup)
    return files, old_files, moves, fell_back, missing


# The commit whose CMakeLists the files/ versions were written from (the 3-way merge base).
BASE_COMMIT = "3fe7dee"


def install(repo, rel):
    src, dst = os.path.join(FILES, rel), os.path.join(repo, rel)
    os.makedirs(os.path.dirname(dst) or repo, exist_ok=True)
    old = subprocess.run(["git", "-C", repo, "show", f"{BASE_COMMIT}:{rel}"], capture_output=True, text=True)
    if os.path.exists(dst) and old.returncode == 0:
        cur = open(dst).read()
        if cur != old.stdout:
            base = os.path.join(repo, ".git-relayout-base")
            open(base, "w").write(old.stdout)
            r = subprocess.run(["git", "merge-file", "-p", dst, base, src], capture_output=True, text=True)
            os.remove(base)
            if r.returncode != 0:
                die(f"{rel} changed on main since {BASE_COMMIT} and the 3-way merge conflicts; port the "
                    f"change into files/{rel} and move BASE_COMMIT:", r.stdout.splitlines())
            open(dst, "w").write(r.stdout)
            print(f"  merged {rel} (main had changed it)")
            return
    shutil.copyfile(src, dst)
    print(f"  installed {rel}")


def edit_once(repo, rel, old, new, required=True):
    p = os.path.join(repo, rel)
    text = open(p).read()
    if new in text:
        return
    if old not in text:
        if required:
            die(f"{rel}: anchor not found", [old])
        return
    open(p, "w").write(text.replace(old, new, 1))


README_LAYOUT = """| path | |
|---|---|
| `proto/armature/v1/` | the API |
| `base/` | what everything shares: the error type (`armature/base/status.h`) |
| `engine/` | the animation library (Eigen only, no gRPC, no I/O beyond parsing bytes), one folder per concern in `src/` and `include/armature/engine/`: `math`, `anim`, `io`, `kinematics`, `mesh`, `deform`, `parallel` |
| `server/` | `armature-server`: `rpc/` (shared by the services: status mapping, validation, limits, metrics, pacing), `assets/` (store, import, asset service), one folder per service (`pose/`, `mesh/`, `ik/`, `deform/`), `host/` (wiring, config, HTTP, auth, TLS, main; `host/gateway/` the REST transcoder) |
| `web/` | the browser viewer (three.js, bundled with esbuild) and its browser and OpenAPI tests |
| `client/` | `libarmature-client` and the `armature` CLI |
| `tests/` | `engine/<concern>/` unit tests (helpers in `engine/testing/`), `server/` unit tests, `integration/` tests against a real server by API area (harness in `integration/support/`), reference scripts |
| `bench/` | Google Benchmark programs (`make bench`) |
| `deploy/` | container image, Compose and Kubernetes files, the image test and the manifest validator |

[ARCHITECTURE.md](ARCHITECTURE.md) draws the layers and the path of one request through the folders.
"""


def migrate(repo):
    files, old_files, moves, fell_back, missing = plan(repo)
    if missing:
        print("note: in the table but not in the tree (skipped):", *missing, sep="\n  ")
    if fell_back:
        print("note: not in the table, placed by fallback rule:", *[f"{o} -> {n}" for o, n in fell_back.items()],
              sep="\n  ")
    full_map = {p: moves.get(p, p) for p in files}
    with open(os.path.join(HERE, "moves.md"), "w") as f:  # the moves actually made, fallbacks included
        f.write(table_markdown(moves))

    # 1. move
    for o, n in sorted(moves.items()):
        os.makedirs(os.path.join(repo, posixpath.dirname(n)), exist_ok=True)
        git(repo, "mv", o, n)
    print(f"moved {len(moves)} files")

    # 2. includes and path references
    refs = reference_map(moves)
    problems = []
    skip = set(INSTALLED)
    changed = 0
    for o in files:
        n = full_map[o]
        if n in skip or not is_text_target(n):
            continue
        path = os.path.join(repo, n)
        try:
            text = open(path, encoding="utf-8").read()
        except (UnicodeDecodeError, FileNotFoundError):
            continue
        new = text
        if is_cpp(n):
            new = rewrite_includes(new, o, n, old_files, full_map, problems)
        new = replace_references(new, refs)
        if new != text:
            open(path, "w", encoding="utf-8").write(new)
            changed += 1
    if problems:
        die("includes that cannot be spelled after the move:", problems)
    print(f"rewrote includes/references in {changed} files")

    # 3. installed files and small edits
    for rel in INSTALLED:
        install(repo, rel)
    edit_once(repo, "CMakeLists.txt", "add_subdirectory(engine)", "add_subdirectory(base)\nadd_subdirectory(engine)")
    edit_once(repo, "deploy/Dockerfile", "COPY engine engine", "COPY base base\nCOPY engine engine")
    edit_once(repo, ".dockerignore", "!engine", "!base\n!engine")
    readme = os.path.join(repo, "README.md")
    text = open(readme).read()
    new = re.sub(r"(## Layout\n\n)\| path \| \|\n(?:\|.*\|\n)+", lambda m: m.group(1) + README_LAYOUT, text)
    if new == text:
        die("README.md: the Layout table was not found", [])
    open(readme, "w").write(new)
    git(repo, "add", "-A", "--", *INSTALLED, "README.md", "CMakeLists.txt", "deploy/Dockerfile", ".dockerignore")
    git(repo, "add", "-u")
    return check(repo)


# ---------------------------------------------------------------- check
MAX_SOURCES = 15
# Each folder may include only folders of a lower rank: no cycles, slices (equal rank) never include
# each other. tests/, bench/ and client/ are unranked (they may use anything they link).
RANK = {"base": 0, "engine/math": 1, "engine/parallel": 1, "engine/anim": 2, "engine/kinematics": 3,
        "engine/mesh": 4, "engine/deform": 5, "engine/io": 6,
        "server/rpc": 10, "server/assets": 11, "server/pose": 12, "server/mesh": 12, "server/ik": 12,
        "server/deform": 12, "server/host": 13}
SLICES = {"server/pose", "server/mesh", "server/ik", "server/deform"}
# Known at the time of writing; each has a fix planned in NOTES.md. Anything else fails.
KNOWN = {
    "layer: engine/mesh -> engine/deform",   # mesh/deform.cc uses NearestRotation from deform/arap.h
    "layer: server/rpc -> server/assets",    # rpc/proto_convert.h: asset conversion needs asset_store.h
    "layer: server/rpc -> server/host",      # rpc/session_admission.cc: AuthorizationOf from host/auth_gate.h
}


def folder_of(p):
    """The concern folder a file belongs to, or None."""
    parts = p.split("/")
    if p.startswith("base/"):
        return "base"
    if p.startswith("engine/include/armature/engine/") and len(parts) > 5:
        return "engine/" + parts[4]
    if p.startswith("engine/src/") and len(parts) > 3:
        return "engine/" + parts[2]
    if p.startswith("server/") and len(parts) > 2:
        return "server/" + parts[1]  # host/gateway counts as host
    if p.startswith("tests/"):
        return "tests"
    if p.startswith(("bench/", "client/")):
        return parts[0]
    return None


def sccs(graph):
    index, low, stack, on, out, i = {}, {}, [], set(), [], [0]

    def strong(v):
        index[v] = low[v] = i[0]; i[0] += 1; stack.append(v); on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                strong(w); low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop(); on.discard(w); comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))
    for v in list(graph):
        if v not in index:
            strong(v)
    return out


def check(repo):
    files = tracked(repo)
    fileset = set(files)
    errors, warnings = [], []
    # Folder sizes.
    count = defaultdict(int)
    for p in files:
        if p.endswith((".cc", ".cpp")) and p.startswith(("base/", "engine/", "server/", "tests/", "bench/", "client/")):
            count[posixpath.dirname(p)] += 1
    for d, c in sorted(count.items()):
        if c > MAX_SOURCES:
            (warnings if d in ("tests/integration", "bench") else errors).append(
                f"size: {d} holds {c} source files directly (> {MAX_SOURCES})")
    # Nothing left flat.
    for p in files:
        d = posixpath.dirname(p)
        if is_cpp(p) and d in ("engine/src", "engine/include/armature/engine", "server", "tests/engine", "server/gateway"):
            errors.append(f"flat: {p} is not in a concern folder")
    # Headers and sources in matching folders.
    srcs = defaultdict(list)
    for p in files:
        if p.endswith(".cc"):
            srcs[posixpath.splitext(posixpath.basename(p))[0]].append(p)
    for p in files:
        if not p.endswith(".h") or not p.startswith(("engine/", "server/")):
            continue
        stem = posixpath.splitext(posixpath.basename(p))[0]
        for s in srcs.get(stem, []):
            if s.startswith(("engine/", "server/")) and folder_of(s) != folder_of(p):
                errors.append(f"match: {p} and {s} are in different folders")
        if p.startswith("engine/include/armature/engine/"):
            c = folder_of(p).split("/")[1]
            if not os.path.isdir(os.path.join(repo, "engine/src", c)) and not any(
                    x.startswith(f"engine/src/{c}/") for x in files):
                warnings.append(f"match: {p} has no engine/src/{c}/ (header-only concern)")
    # Include graph between folders.
    edges = defaultdict(set)
    why = {}
    roots = ["base/include", "engine/include", "engine/src", "", "client/include"]
    for p in files:
        if not is_cpp(p):
            continue
        src_folder = folder_of(p)
        if src_folder is None:
            continue
        text = open(os.path.join(repo, p), encoding="utf-8", errors="replace").read()
        for m in INCLUDE_RX.finditer(text):
            q, name = m.group(2), m.group(3)
            target = None
            if q == '"':
                c = posixpath.normpath(posixpath.join(posixpath.dirname(p), name))
                if c in fileset:
                    target = c
            if target is None:
                for r in roots:
                    c = posixpath.normpath(posixpath.join(r, name)) if r else posixpath.normpath(name)
                    if c in fileset:
                        target = c
                        break
            if target is None:
                if q == '"' and not name.startswith(("armature/v1/", "google/", "grpc/")) and not name.endswith(".pb.h"):
                    errors.append(f"include: {p} includes \"{name}\", which is not in the tree")
                continue
            dst = folder_of(target)
            if dst is None or dst == src_folder:
                continue
            edges[src_folder].add(dst)
            why.setdefault((src_folder, dst), f"{p} includes {target}")
    upward = set()
    for a, outs in sorted(edges.items()):
        for b in sorted(outs):
            if a in RANK and b in RANK and RANK[b] >= RANK[a]:
                kind = "slice" if a in SLICES and b in SLICES else "layer"
                upward.add((a, b))
                errors.append((f"{kind}: {a} -> {b}", why[(a, b)]))
            elif a in RANK and b not in RANK:
                errors.append((f"layer: {a} -> {b}", why[(a, b)]))
    for comp in sccs({k: sorted(v) for k, v in edges.items()}):
        cause = [f"{a} -> {b}" for a, b in sorted(upward) if a in comp and b in comp]
        if cause:
            warnings.append(f"cycle {', '.join(comp)}: closed by {'; '.join(cause)}")
        else:
            errors.append(("cycle: " + ", ".join(comp), "between unranked folders"))
    # ARMATURE_TEST_DIR-relative paths must exist (tests/ is ARMATURE_TEST_DIR).
    for p in files:
        if p.startswith("tests/") and is_cpp(p):
            text = open(os.path.join(repo, p), encoding="utf-8", errors="replace").read()
            for m in re.finditer(r'ARMATURE_TEST_DIR[^"\n]*"/?([\w./-]+?)/?"', text):
                rel = m.group(1).split("/")[0]
                if rel and not os.path.exists(os.path.join(repo, "tests", rel)):
                    errors.append(f"testdir: {p} uses ARMATURE_TEST_DIR \"{m.group(1)}\", missing")
    # Stale mentions of old paths anywhere in text files.
    stale_rx = re.compile(r"(?<![\w.-])(?<![\w-]/)(" + "|".join(re.escape(o) for o in sorted(MOVES, key=len, reverse=True))
                          + r")(?![\w])")
    for p in files:
        if is_text_target(p) and os.path.exists(os.path.join(repo, p)):
            text = open(os.path.join(repo, p), encoding="utf-8", errors="replace").read()
            for m in stale_rx.finditer(text):
                if m.group(1) not in fileset:
                    errors.append(f"stale: {p} mentions {m.group(1)}")

    errors = [e if isinstance(e, tuple) else (e, "") for e in errors]
    keys = {k for k, _ in errors}
    known = [f"{k} ({w})" for k, w in errors if k in KNOWN]
    unknown = [f"{k} ({w})" if w else k for k, w in errors if k not in KNOWN]
    print(f"\ncheck: {len(files)} files, folder include graph:")
    for a in sorted(edges):
        print(f"  {a} -> {', '.join(sorted(edges[a]))}")
    for w in warnings:
        print(f"  warning {w}")
    for k in known:
        print(f"  KNOWN (fix by hand, see NOTES.md) {k}")
    for k in sorted(KNOWN - keys):
        print(f"  fixed (drop from KNOWN) {k}")
    if unknown:
        die("check found problems:", unknown)
    print("check: OK" + (f" ({len(known)} known violations left)" if known else ""))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("repo", nargs="?")
    ap.add_argument("--check", action="store_true", help="only verify a migrated tree")
    ap.add_argument("--table", action="store_true", help="print the move table as Markdown")
    ap.add_argument("--dry-run", action="store_true", help="plan only: coverage and the moves")
    a = ap.parse_args()
    if a.table:
        sys.stdout.write(table_markdown(MOVES))
        return 0
    if not a.repo:
        ap.error("REPO is required")
    repo = os.path.abspath(a.repo)
    if a.check:
        return check(repo)
    if a.dry_run:
        _, _, moves, fell_back, missing = plan(repo)
        print(f"{len(moves)} moves; fallback: {fell_back}; missing: {missing}")
        return 0
    if git(repo, "status", "--porcelain", "--untracked-files=no").strip():
        die("the work tree has uncommitted changes; commit or stash them first", [])
    return migrate(repo)


if __name__ == "__main__":
    sys.exit(main())
