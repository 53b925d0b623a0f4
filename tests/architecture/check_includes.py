"""ARCHITECTURE.md's include rules, checked on every source and header.

- engine: math <- anim <- kinematics <- mesh <- deform <- io, each folder
  using only those on its left (and base); parallel (the worker pool) is
  used by mesh and deform and uses nothing of ours.
- base uses nothing of ours.
- server: rpc <- assets <- the slices (pose, mesh, ik, deform, authoring)
  <- host (host/gateway is part of host). Slices never include each other.
  Inside rpc: its top (status, validation, limits) <- rpc/convert <-
  rpc/work <- rpc/streams.
- inside host/gateway: common/ (the call factory) uses no protocol folder;
  rest/ and grpc_web/ use common/ only; websocket/ (sessions on REST paths)
  uses common/, rest/ and grpc_web/ (its base64); nothing includes the
  router (gateway.h, cors.h) but host/ itself.
- clients/cpp/ talks to the server over gRPC only: nothing of server/ or engine/.
- No include cycle between folders (the rules above are an order, and the
  graph is checked for cycles as well).

usage: check_includes.py REPO_ROOT
"""
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
ENGINE_ORDER = ["math", "anim", "kinematics", "mesh", "deform", "io"]
SLICES = ["pose", "mesh", "ik", "deform", "authoring", "crowd"]


def folder_of_file(path):
    """The layer a source or header belongs to, e.g. 'engine/anim', 'server/pose'."""
    parts = path.split("/")
    if parts[0] == "engine":
        concern = parts[2] if parts[1] == "src" else parts[4] if parts[1] == "include" and len(parts) > 4 else None
        return f"engine/{concern}" if concern else None
    if parts[0] == "server":
        if parts[1] == "rpc" and len(parts) > 3:
            return f"server/rpc/{parts[2]}"
        return "server/host" if parts[1] == "host" else f"server/{parts[1]}"
    if parts[0] == "base":
        return "base"
    if parts[:2] == ["clients", "cpp"]:
        return "clients/cpp"
    return None


def folder_of_include(include, includer_folder):
    """The layer an #include "..." names; None for generated or third-party headers."""
    m = re.match(r"armature/engine/([a-z_]+)/", include)
    if m:
        return f"engine/{m.group(1)}"
    if include.startswith("armature/base/"):
        return "base"
    if include == "armature/client.h":
        return "clients/cpp"
    m = re.match(r"server/rpc/([a-z_]+)/", include)
    if m:
        return f"server/rpc/{m.group(1)}"
    m = re.match(r"server/([a-z_]+)/", include)
    if m:
        return "server/host" if m.group(1) == "host" else f"server/{m.group(1)}"
    first = include.split("/")[0]
    if includer_folder.startswith("engine/") and first in ENGINE_ORDER + ["parallel"] and "/" in include:
        return f"engine/{first}"  # engine/src/<concern>/ relative: "parallel/worker_pool.h"
    return None if "/" in include else includer_folder  # a header beside the file


def allowed(src, dst):
    if src == dst or dst is None:
        return True
    if src == "base":
        return False
    if src.startswith("engine/"):
        a, b = src[7:], dst[7:] if dst.startswith("engine/") else None
        if dst == "base":
            return True
        if b is None:
            return False
        if a == "parallel":
            return False
        if b == "parallel":
            return a in ("mesh", "deform")
        return a in ENGINE_ORDER and b in ENGINE_ORDER and ENGINE_ORDER.index(b) < ENGINE_ORDER.index(a)
    if src.startswith("server/"):
        if dst == "base" or dst.startswith("engine/"):
            return True
        if dst == "clients/cpp":
            return False
        order = {"server/rpc": 0, "server/rpc/convert": 0.1, "server/rpc/work": 0.2, "server/rpc/streams": 0.3,
                 "server/assets": 1, "server/host": 3}
        rank = lambda f: order.get(f, 2)  # the slices sit between assets and host
        if rank(src) == 2 and rank(dst) == 2:
            return False  # slices never include each other
        return rank(dst) < rank(src)
    if src == "clients/cpp":
        return dst in ("base", "clients/cpp")
    return True


GATEWAY = "server/host/gateway/"
# What each folder of the gateway may use of the others; "router" is the
# top (gateway.h, cors.h), which only host/ and the router itself use.
GATEWAY_USES = {
    "common": set(),
    "rest": {"common"},
    "grpc_web": {"common"},
    "websocket": {"common", "rest", "grpc_web"},
}


def gateway_part(path):
    """'common', 'rest', … for a file in server/host/gateway/<part>/, 'router' at its top, else None."""
    if not path.startswith(GATEWAY):
        return None
    first = path[len(GATEWAY):].split("/")
    return first[0] if len(first) > 1 else "router"


def gateway_allowed(rel, include):
    src, dst = gateway_part(rel), gateway_part(include)
    if dst is None or src == dst:
        return True
    if dst == "router":
        return src is None or src == "router"  # host/ wires the gateway
    if src is None or src == "router":
        return True
    return dst in GATEWAY_USES.get(src, set())


def find_cycle(edges):
    graph = {}
    for a, b in edges:
        graph.setdefault(a, set()).add(b)
    state = {}

    def visit(node, path):
        state[node] = 1
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return path + [node, nxt]
            if not state.get(nxt):
                found = visit(nxt, path + [node])
                if found:
                    return found
        state[node] = 2
        return None

    for node in sorted(graph):
        if not state.get(node):
            found = visit(node, [])
            if found:
                return found
    return None


def main():
    root = os.path.abspath(sys.argv[1])
    problems, edges, files = [], set(), 0
    for top in ("base", "engine", "server", "clients/cpp"):
        for dirpath, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if not name.endswith((".h", ".cc")):
                    continue
                rel = os.path.relpath(os.path.join(dirpath, name), root)
                src = folder_of_file(rel)
                if src is None:
                    continue
                files += 1
                text = open(os.path.join(root, rel), encoding="utf-8", errors="replace").read()
                for include in INCLUDE.findall(text):
                    dst = folder_of_include(include, src)
                    if dst and dst != src:
                        edges.add((src, dst))
                    if not allowed(src, dst):
                        problems.append(f'{rel}: #include "{include}": {src} may not use {dst}')
                    elif not gateway_allowed(rel, include):
                        problems.append(f'{rel}: #include "{include}": gateway/{gateway_part(rel)} may not use '
                                        f'gateway/{gateway_part(include)}')
    cycle = find_cycle(edges)
    if cycle:
        problems.append("an include cycle between folders: " + " -> ".join(cycle))
    for p in problems:
        print("FAIL:", p)
    print(f"{files} files, {len(edges)} folder edges checked, {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
