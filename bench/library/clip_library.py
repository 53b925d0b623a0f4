"""A clip library held by a real server (issue 30): imports N copies of the
shared BVH files under different names into a fresh armature-server, then
reports its RSS and armature_assets_memory_bytes, each per joint-sample of
the clips held (joints x frames, summed over the clips), beside an empty
server's RSS. Loopback only; the data dir is a temporary directory.

usage: clip_library.py SERVER_BIN CLI_BIN SHARED_DATA_DIR [N=500] [CLIP_ERROR]
"""
import glob
import json
import os
import re
import subprocess
import sys
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "reference"))
from server_fixture import Server  # noqa: E402


def rss_bytes(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    return 0


def metric(http_port, name):
    text = urllib.request.urlopen(f"http://127.0.0.1:{http_port}/metrics", timeout=30).read().decode()
    m = re.search(rf"^{name}(?:{{[^}}]*}})? (\S+)$", text, re.M)
    return float(m.group(1)) if m else 0.0


def main():
    server_bin, cli, data = sys.argv[1:4]
    count = int(sys.argv[4]) if len(sys.argv) > 4 else 500
    clip_error = sys.argv[5] if len(sys.argv) > 5 else ""
    files = sorted(glob.glob(os.path.join(data, "bvh", "*.bvh")))
    if not files:
        print(f"SKIP: no BVH file in {data}/bvh")
        return 0
    args = ["--no-demo", "--max-assets-mb", "100000"] + (["--clip-error", clip_error] if clip_error else [])
    with Server(server_bin, args) as server:
        time.sleep(0.5)
        empty_rss = rss_bytes(server.proc.pid)
        joint_samples, clips, started = 0, 0, time.time()
        for i in range(count):
            path = files[i % len(files)]
            r = subprocess.run([cli, "--server", server.target, "import", path, "--name", f"lib{i:04d}"],
                               capture_output=True, text=True)
            if r.returncode != 0:
                raise RuntimeError(f"import {i} failed: {r.stderr}")
            for clip in json.loads(r.stdout)["clips"]:
                joint_samples += round(clip["runtimeBytes"] / clip["bytesPerJointSample"]) \
                    if clip["bytesPerJointSample"] else 0
                clips += 1
        seconds = time.time() - started
        rss = rss_bytes(server.proc.pid)
        memory = metric(server.http_port, "armature_assets_memory_bytes")
    print(json.dumps({
        "clips": clips, "joint_samples": joint_samples, "import_seconds": round(seconds, 1),
        "clip_error": clip_error or "server default",
        "empty_rss_mb": round(empty_rss / 2**20, 1), "rss_mb": round(rss / 2**20, 1),
        "rss_bytes_per_joint_sample": round(rss / joint_samples, 3),
        "rss_over_empty_bytes_per_joint_sample": round((rss - empty_rss) / joint_samples, 3),
        "assets_memory_bytes": int(memory),
        "assets_memory_bytes_per_joint_sample": round(memory / joint_samples, 3),
    }, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
