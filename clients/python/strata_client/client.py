"""StrataClient: one robot, over the WebSocket (streams, goals, teleop) and REST (maps, one-off reads)."""

from __future__ import annotations

import math
import re
import time
from typing import Any, Callable, Iterable, Optional

from .connection import SUBPROTOCOL, Connection, check_protocol_version
from .errors import StrataError
from .frames import OccupancyFrame, TileFrame
from .goals import Goal, check_coordinate
from .maps import Maps
from .messages import STREAMS, GoalState, Hello, Path, Pose, Relocalization, Status
from .rest import RestClient, http_base_url
from .teleop import Teleop

# proto/PROTOCOL.md "Who may do what": 16-128 characters of A-Z a-z 0-9 - _.
TOKEN = re.compile(r"[A-Za-z0-9_-]{16,128}")


def check_token(token: Optional[str]) -> Optional[str]:
    if token is not None and not TOKEN.fullmatch(token):
        raise ValueError("an operator token is 16-128 characters of A-Z a-z 0-9 - _")
    return token


class StrataClient:
    """A connection to one strata server. Without a token it is a viewer: it may watch but not move the robot.

    `url` is the server's address (http://host:port, https:// with TLS; ws:// and wss:// are taken too).
    `ca_file` verifies a server whose certificate a private CA (or the server itself) signed.
    Every wait takes a timeout in seconds of wall time; `timeout` is the default for requests.
    """

    def __init__(self, url: str, token: Optional[str] = None, *, ca_file: Optional[str] = None,
                 timeout: float = 10.0, check_version: bool = True) -> None:
        self.url = http_base_url(url)
        self.timeout = timeout
        self.rest = RestClient(self.url, check_token(token), ca_file, timeout)
        self.maps = Maps(self.rest)
        try:
            if check_version:
                # REST says the protocol before any WebSocket: a clear refusal of another major version.
                info = self.rest.get_json("/api/v1/info")
                check_protocol_version(info.get("protocol"), info.get("protocol_version"), "/api/v1/info")
            ws_url = ("wss" if self.url.startswith("https") else "ws") + self.url[self.url.index("://"):] + "/ws"
            self.connection = Connection(ws_url, token, ca_file, timeout)
        except BaseException:
            self.rest.close()
            raise
        self._teleop: Optional[Teleop] = None

    # --- who and what ------------------------------------------------------------------------------------
    @property
    def hello(self) -> Hello:
        return self.connection.hello

    @property
    def role(self) -> str:
        """"operator" or "viewer", as the server's hello said."""
        return self.connection.hello.role

    @property
    def protocol(self) -> str:
        return SUBPROTOCOL

    # --- the newest state from the streams (None before the first message) -----------------------------
    @property
    def pose(self) -> Optional[Pose]:
        return self.connection.latest("pose")

    @property
    def status(self) -> Optional[Status]:
        return self.connection.latest("status")

    @property
    def goal_state(self) -> Optional[GoalState]:
        return self.connection.latest("goal")

    @property
    def path(self) -> Optional[Path]:
        return self.connection.latest("path")

    @property
    def occupancy(self) -> Optional[OccupancyFrame]:
        return self.connection.occupancy()

    @property
    def tiles(self) -> dict[tuple[int, int], TileFrame]:
        """The map's tiles as received, by (tile_x, tile_y); removed tiles are dropped."""
        return self.connection.tiles()

    def on(self, kind: str, listener: Callable[[Any], None]) -> Callable[[], None]:
        """Calls `listener` with every `kind` ("pose", "status", "goal", "path", "tile", "occupancy", "error",
        "message") on the reader thread; returns the function that removes it. Keep listeners quick."""
        return self.connection.on(kind, listener)

    # --- waiting -----------------------------------------------------------------------------------------
    def wait_for(self, kind: str, predicate: Callable[[Any], bool] = lambda _: True, timeout: float = 30.0) -> Any:
        """The newest `kind` state ("pose", "status", "goal", "path") satisfying `predicate`, waiting for it."""
        def ready(connection: Connection) -> Any:
            value = connection.latest(kind)
            return value if value is not None and predicate(value) else None
        return self.connection.wait_until(ready, timeout)

    def wait_for_pose(self, timeout: float = 30.0) -> Pose:
        return self.wait_for("pose", timeout=timeout)

    def wait_for_map(self, min_version: int = 1, timeout: float = 60.0) -> Status:
        """Waits for a status reporting a map of at least `min_version` (the first scan is in): goals need
        known ground."""
        return self.wait_for("status", lambda status: status.map_version >= min_version, timeout)

    def wait_until_still(self, seconds: float = 0.5, tolerance: float = 1e-3, timeout: float = 30.0) -> Pose:
        """Waits until the pose estimate has moved less than `tolerance` m and rad over `seconds` of robot time."""
        deadline = time.monotonic() + timeout
        anchor = self.wait_for_pose(timeout)
        while True:
            pose = self.wait_for("pose", lambda p: p.stamp >= anchor.stamp + seconds,
                                 max(0.0, deadline - time.monotonic()))
            if (abs(pose.x - anchor.x) < tolerance and abs(pose.y - anchor.y) < tolerance
                    and abs(pose.yaw - anchor.yaw) < tolerance):
                return pose
            anchor = pose

    # --- commands ----------------------------------------------------------------------------------------
    def ping(self) -> float:
        """Round trip to the server, s."""
        start = time.monotonic()
        self.connection.request({"op": "ping"})
        return time.monotonic() - start

    def subscribe(self, streams: Iterable[str]) -> None:
        """Receive only these streams (of pose, status, tiles, occupancy, path, goal). The goal stream stays
        on: Goal handles follow it."""
        chosen = list(dict.fromkeys(streams))
        unknown = [s for s in chosen if s not in STREAMS]
        if unknown:
            raise ValueError(f"unknown streams {unknown}; the streams are {', '.join(STREAMS)}")
        if "goal" not in chosen:
            chosen.append("goal")
        self.connection.request({"op": "subscribe", "streams": chosen})

    def set_goal(self, x: float, y: float, z: Optional[float] = None) -> Goal:
        """Operator: drive to (x, y) on the level nearest z (without z: the robot's own). Replaces any goal.
        Returns once the server accepted it; `Goal.wait()` follows it. The goal is cancelled when this
        connection closes."""
        message: dict[str, Any] = {"op": "set_goal", "x": check_coordinate("x", x), "y": check_coordinate("y", y)}
        if z is not None:
            message["z"] = check_coordinate("z", z)
        after_id = self.connection.max_goal_id()
        self.connection.request(message)
        return Goal(self.connection, message["x"], message["y"], message.get("z"), after_id)

    def set_pose(self, x: float, y: float, yaw: float, z: Optional[float] = None,
                 timeout: float = 30.0) -> Relocalization:
        """Operator: the robot is at (x, y) facing `yaw` (radians) on the level nearest z, in the saved map it
        localizes in (`maps.load(name, mode="localize")`). The server searches within 2 m and 30 degrees of it
        and places the robot where it finds it; returns what the search found (`found`, and `message`: where,
        or why not). Refused (StrataError bad_params) while the robot maps."""
        if isinstance(yaw, bool) or not isinstance(yaw, (int, float)) or not abs(yaw) <= 2 * math.pi:
            raise ValueError(f"the pose's yaw must be radians within +-2 pi, not {yaw!r}")
        message: dict[str, Any] = {"op": "set_pose", "x": check_coordinate("x", x), "y": check_coordinate("y", y),
                                   "yaw": float(yaw)}
        if z is not None:
            message["z"] = check_coordinate("z", z)
        before = self.connection.latest("status")
        earlier = before.raw.get("relocalization") if before is not None else None
        self.connection.request(message)
        status = self.wait_for("status", lambda s: s.raw.get("relocalization") not in (None, earlier), timeout)
        return Relocalization.from_json(status.raw["relocalization"])

    def cancel_goal(self) -> None:
        """Operator: cancel the goal and stop."""
        self.connection.request({"op": "cancel_goal"})

    def teleop(self, v: float, w: float) -> Teleop:
        """Operator: drive at v m/s and w rad/s until `.stop()` (or the `with` block ends); a thread renews the
        0.5 s command lease. Cancels a goal. A running teleop is replaced."""
        if self._teleop is not None and self._teleop.active:
            self._teleop.set(v, w)
            return self._teleop
        self._teleop = Teleop(self.connection, v, w)
        return self._teleop

    def stop(self) -> None:
        """Operator: stop teleoperating, or stop a robot following its built-in demo route (a zero teleop)."""
        if self._teleop is not None and self._teleop.active:
            self._teleop.stop()
        else:
            self.connection.request({"op": "teleop", "v": 0.0, "w": 0.0})

    def errors(self) -> list[StrataError]:
        """Errors the server sent for messages without an id (the teleop keep-alive), taken from the client."""
        return self.connection.take_errors()

    # --- closing -----------------------------------------------------------------------------------------
    def close(self) -> None:
        if self._teleop is not None and self._teleop.active:
            try:
                self._teleop.stop()
            except Exception:  # closing must not fail because the robot can no longer be told to stop
                pass
        self.connection.close()
        self.rest.close()

    def __enter__(self) -> "StrataClient":
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()


def connect(url: str, token: Optional[str] = None, *, ca_file: Optional[str] = None,
            timeout: float = 10.0) -> StrataClient:
    """Connects to a strata server; see StrataClient."""
    return StrataClient(url, token, ca_file=ca_file, timeout=timeout)
