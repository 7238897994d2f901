"""Checking messages against the protocol's JSON Schemas (proto/schemas/): the API tests check everything the
server sends and everything the client sends, so the client and proto/ cannot drift apart unnoticed."""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path
from typing import Any, Optional

import jsonschema

from .frames import Frame, OccupancyFrame, TileFrame, png_size

# REST paths whose 2xx JSON bodies have a schema in proto/schemas/rest/.
_REST_SCHEMAS = {
    ("GET", "/healthz"): "health", ("GET", "/api/v1/info"): "info", ("GET", "/api/v1/pose"): "pose",
    ("GET", "/api/v1/status"): "status", ("GET", "/api/v1/goal"): "goal", ("POST", "/api/v1/goal"): "goal",
    ("DELETE", "/api/v1/goal"): "goal", ("GET", "/api/v1/path"): "path", ("GET", "/api/v1/maps"): "maps",
    ("GET", "/api/v1/tiles"): "tiles", ("GET", "/api/v1/sim/world"): "sim_world",
}


def find_proto_dir() -> Optional[Path]:
    """STRATA_PROTO_DIR from the environment, else proto/ of the source tree this package sits in."""
    from_env = os.environ.get("STRATA_PROTO_DIR")
    if from_env:
        return Path(from_env)
    in_tree = Path(__file__).resolve().parents[3] / "proto"
    return in_tree if (in_tree / "schemas").is_dir() else None


class ProtocolChecker:
    """Collects every way a message breaks its schema. Thread-safe: the reader threads report here."""

    def __init__(self, proto_dir: Path) -> None:
        self.proto_dir = Path(proto_dir)
        self._validators: dict[tuple[str, str], Any] = {}
        self._lock = threading.Lock()
        self.violations: list[str] = []
        self.checked = 0

    def _validator(self, group: str, name: str) -> Optional[Any]:
        key = (group, name)
        with self._lock:
            if key not in self._validators:
                path = self.proto_dir / "schemas" / group / f"{name}.schema.json"
                if path.exists():
                    schema = json.loads(path.read_text())
                    jsonschema.Draft7Validator.check_schema(schema)
                    self._validators[key] = jsonschema.Draft7Validator(schema)
                else:
                    self._validators[key] = None
            return self._validators[key]

    def check(self, group: str, name: str, message: Any, what: str) -> None:
        validator = self._validator(group, name)
        with self._lock:
            self.checked += 1
            if validator is None:
                self.violations.append(f"{what}: no schema {group}/{name}.schema.json for {json.dumps(message)[:300]}")
                return
            for error in validator.iter_errors(message):
                self.violations.append(f"{what} breaks {group}/{name}: {error.message} at "
                                       f"{'/'.join(map(str, error.absolute_path))}: {json.dumps(message)[:300]}")

    # Observers for Connection and RestClient -------------------------------------------------------------
    def on_message(self, direction: str, message: dict[str, Any]) -> None:
        group = "ws-server" if direction == "received" else "ws-client"
        self.check(group, str(message.get("op")), message, f"{direction} {message.get('op')}")

    def on_frame(self, frame: Frame) -> None:
        with self._lock:
            self.checked += 1
            problem = None
            if frame.header.layout_version != 1:
                problem = f"layout version {frame.header.layout_version}"
            elif isinstance(frame, TileFrame):
                if frame.header.header_bytes != 40:
                    problem = f"tile header_bytes {frame.header.header_bytes}"
                elif frame.draco and not frame.draco.startswith(b"DRACO"):
                    problem = "tile payload is not a Draco bitstream"
            elif isinstance(frame, OccupancyFrame):
                if frame.header.header_bytes != 64:
                    problem = f"occupancy header_bytes {frame.header.header_bytes}"
                else:
                    try:
                        if png_size(frame.png) != (frame.width, frame.height):
                            problem = f"PNG size {png_size(frame.png)} is not the frame's {frame.width}x{frame.height}"
                    except ValueError as bad:
                        problem = str(bad)
            else:
                problem = f"unknown frame kind {frame.header.kind}"
            if problem:
                self.violations.append(f"binary frame: {problem}")

    def on_response(self, method: str, path: str, status: int, body: Any) -> None:
        if status >= 400:
            if body is None:
                with self._lock:
                    self.violations.append(f"{method} {path}: HTTP {status} without a JSON error body")
                return
            self.check("rest", "error", body, f"{method} {path} ({status})")
        elif (method, path) in _REST_SCHEMAS and status != 304:
            self.check("rest", _REST_SCHEMAS[(method, path)], body, f"{method} {path}")

    def watch(self, client: Any) -> Any:
        """Checks everything `client` (a StrataClient) sends and receives from now on; returns it."""
        client.connection.add_message_observer(self.on_message)
        client.connection.add_frame_observer(self.on_frame)
        client.rest.add_observer(self.on_response)
        return client

    def take_violations(self) -> list[str]:
        with self._lock:
            violations, self.violations = self.violations, []
            return violations
