"""Teleoperation: the server obeys a teleop command for 0.5 s only, so a thread repeats it while it is held.
Each command carries a sequence number and when it was sent on the server's clock, so that commands a link
outage held back never move the robot when they arrive (proto/PROTOCOL.md, "Teleoperation")."""

from __future__ import annotations

import itertools
import math
import threading
from typing import TYPE_CHECKING, Optional

from .errors import ConnectionClosed, StrataError

if TYPE_CHECKING:
    from .connection import Connection

LEASE_SECONDS = 0.5  # proto/PROTOCOL.md: a teleop command expires 0.5 s after the last one
RESEND_SECONDS = 0.1  # 10 Hz: five commands per lease, well within the 40 messages/s rate limit
MAX_V = 2.0  # m/s, proto/schemas/ws-client/teleop.schema.json; the base clamps to its own limits
MAX_W = 3.0  # rad/s


def teleop_command(connection: "Connection", v: float, w: float, seq: int) -> dict:
    """The teleop message, stamped when the server gives its clock."""
    command: dict = {"op": "teleop", "v": v, "w": w}
    now = connection.server_clock_ms()
    if now is not None:
        command.update(seq=seq, t=round(now, 1))
    return command


def check_velocity(v: float, w: float) -> tuple[float, float]:
    for name, value, limit in (("v", v, MAX_V), ("w", w, MAX_W)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError(f"teleop {name} must be a finite number, not {value!r}")
        if abs(value) > limit:
            raise ValueError(f"teleop {name} = {value} is beyond the protocol's +-{limit:g}")
    return float(v), float(w)


class Teleop:
    """Drives at (v, w) until stopped. The first command is acknowledged (a viewer's is refused with
    StrataError unauthorized); then the keep-alive thread resends it without an id every 0.1 s."""

    def __init__(self, connection: "Connection", v: float, w: float) -> None:
        self._connection = connection
        self._v, self._w = check_velocity(v, w)
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self.failure: Optional[BaseException] = None  # why the keep-alive thread ended early, if it did
        self._seq = connection.teleop_sequence
        connection.request(self._command(self._v, self._w))
        self._thread = threading.Thread(target=self._keep_alive, name="strata-teleop", daemon=True)
        self._thread.start()

    @property
    def active(self) -> bool:
        return self._thread.is_alive()

    def set(self, v: float, w: float) -> None:
        """Changes the velocity; sent at once."""
        v, w = check_velocity(v, w)
        with self._lock:  # numbered and sent under the lock: the keep-alive never overtakes it
            self._v, self._w = v, w
            self._connection.send(self._command(v, w))

    def stop(self) -> None:
        """Stops the keep-alive and commands a standstill (acknowledged), rather than letting the lease run out."""
        self._stop.set()
        self._thread.join()
        if not self._connection.closed:
            self._connection.request(self._command(0.0, 0.0))

    def _command(self, v: float, w: float) -> dict:
        return teleop_command(self._connection, v, w, next(self._seq))

    def __enter__(self) -> "Teleop":
        return self

    def __exit__(self, *_exc: object) -> None:
        self.stop()

    def _keep_alive(self) -> None:
        while not self._stop.wait(RESEND_SECONDS):
            try:
                with self._lock:
                    self._connection.send(self._command(self._v, self._w))
            except (ConnectionClosed, StrataError) as failure:
                self.failure = failure
                return
