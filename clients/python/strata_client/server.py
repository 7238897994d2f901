"""Starting and stopping a real `strata serve` process for tests: on a free loopback port, with a known
operator token and a private maps directory."""

from __future__ import annotations

import os
import re
import secrets
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path
from typing import Optional, Sequence

# The one line the server prints on stdout once it listens; with --port 0 it names the port it got.
_SERVING = re.compile(r"strata: serving on (https?)://127\.0\.0\.1:(\d+)")


def find_strata_binary() -> Optional[str]:
    """STRATA_BINARY from the environment, else `strata` on PATH; None when neither is there."""
    from_env = os.environ.get("STRATA_BINARY")
    if from_env:
        return from_env
    return shutil.which("strata")


class StrataServer:
    """A running `strata serve`. `url`, `token` and `maps_dir` say how to reach and inspect it."""

    def __init__(self, binary: str, args: Sequence[str] = (), *, token: Optional[str] = None,
                 maps_dir: Optional[Path] = None, work_dir: Optional[Path] = None,
                 start_timeout: float = 30.0) -> None:
        self.binary = binary
        self.token = token or "test-" + secrets.token_hex(16)
        self._own_dir = None if work_dir else tempfile.mkdtemp(prefix="strata-test-")
        self.work_dir = Path(work_dir or self._own_dir)
        self.maps_dir = Path(maps_dir) if maps_dir else self.work_dir / "maps"
        self.log_path = self.work_dir / "strata.log"
        stdout_path = self.work_dir / "strata.stdout"
        command = [binary, "serve", "--bind", "127.0.0.1", "--port", "0", "--maps-dir", str(self.maps_dir), *args]
        # The token goes in the environment, not the command line, where other users could read it.
        env = {**os.environ, "STRATA_OPERATOR_TOKEN": self.token}
        # stdout to a file rather than a pipe: nobody has to keep reading it for the server to go on.
        with open(stdout_path, "wb") as stdout, open(self.log_path, "wb") as log:
            self.process = subprocess.Popen(command, stdout=stdout, stderr=log, stdin=subprocess.DEVNULL, env=env)
        deadline = time.monotonic() + start_timeout
        while True:
            match = _SERVING.search(stdout_path.read_text(errors="replace"))
            if match:
                break
            if self.process.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError(f"strata did not start serving ({' '.join(command)}); exit "
                                   f"{self.process.returncode}; log:\n{self.log_tail()}")
            time.sleep(0.05)
        self.scheme = match.group(1)
        self.port = int(match.group(2))
        self.url = f"{self.scheme}://127.0.0.1:{self.port}"

    def log_tail(self, lines: int = 40) -> str:
        try:
            return "\n".join(self.log_path.read_text(errors="replace").splitlines()[-lines:])
        except OSError:
            return "(no log)"

    def stop(self) -> int:
        """SIGTERM, then SIGKILL after 10 s; returns the exit status. Removes its own temporary directory."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGTERM)
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self._own_dir:
            shutil.rmtree(self._own_dir, ignore_errors=True)
            self._own_dir = None
        return self.process.returncode

    def __enter__(self) -> "StrataServer":
        return self

    def __exit__(self, *_exc: object) -> None:
        self.stop()
