"""Starts a real armature-server on free ports for Python-driven tests."""
import json
import os
import signal
import subprocess
import tempfile
import time


class Server:
    def __init__(self, server_bin, extra_args=(), data_dir=None):
        self.dir = tempfile.TemporaryDirectory(prefix="armature-py-")
        port_file = os.path.join(self.dir.name, "ports.json")
        self.log = open(os.path.join(self.dir.name, "server.log"), "w+")
        self.proc = subprocess.Popen(
            [server_bin, "--host", "127.0.0.1", "--grpc-port", "0", "--http-port", "0",
             "--data-dir", data_dir or os.path.join(self.dir.name, "data"), "--port-file", port_file, *extra_args],
            stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 60
        while time.time() < deadline:
            if os.path.exists(port_file):
                with open(port_file) as f:
                    ports = json.load(f)
                self.grpc_port, self.http_port = ports["grpc"], ports["http"]
                self.target = f"127.0.0.1:{self.grpc_port}"
                return
            if self.proc.poll() is not None:
                raise RuntimeError("armature-server exited while starting:\n" + self.read_log())
            time.sleep(0.02)
        self.stop()
        raise RuntimeError("armature-server did not start")

    def read_log(self):
        self.log.flush()
        with open(self.log.name) as f:
            return f.read()

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            self.proc.wait(timeout=15)
        self.log.close()
        self.dir.cleanup()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.stop()
