"""Typed views of the protocol's JSON messages (proto/schemas/). Each keeps the message it came from as `raw`:
fields a later protocol version adds are there, and this client ignores them (PROTOCOL.md "Versioning")."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional

JsonObject = dict[str, Any]

GOAL_PHASES = ("none", "accepted", "planning", "driving", "reached", "failed", "cancelled")
FINAL_GOAL_PHASES = frozenset({"reached", "failed", "cancelled"})
STREAMS = ("pose", "status", "tiles", "occupancy", "path", "goal")


@dataclass(frozen=True)
class Hello:
    server: str
    version: str  # the server's version
    protocol: str  # "strata.v1"
    protocol_version: int
    role: str  # "operator" or "viewer"
    raw: JsonObject = field(repr=False, compare=False)

    @staticmethod
    def from_json(m: JsonObject) -> "Hello":
        return Hello(m["server"], m["version"], m["protocol"], int(m["protocol_version"]), m["role"], m)


@dataclass(frozen=True)
class ServerInfo:
    """GET /api/v1/info."""
    name: str
    version: str
    protocol: str
    protocol_version: int
    source: str
    raw: JsonObject = field(repr=False, compare=False)

    @staticmethod
    def from_json(m: JsonObject) -> "ServerInfo":
        return ServerInfo(m["name"], m["version"], m["protocol"], int(m["protocol_version"]), m["source"], m)


@dataclass(frozen=True)
class Pose3:
    x: float
    y: float
    z: float
    roll: float
    pitch: float
    yaw: float

    @staticmethod
    def from_json(m: JsonObject) -> "Pose3":
        return Pose3(m["x"], m["y"], m["z"], m["roll"], m["pitch"], m["yaw"])


@dataclass(frozen=True)
class Pose:
    """The robot's pose estimate in the map frame (m, rad); R = Rz(yaw) Ry(pitch) Rx(roll)."""
    x: float
    y: float
    z: float
    roll: float
    pitch: float
    yaw: float
    stamp: float  # robot time, s
    source: str  # "odometry" until the first scan registered, then "registration"
    mode: Optional[str]  # "driving", "standing", "scanning" or "blocked"
    truth: Optional[Pose3]  # simulator only: the ground truth, for evaluation
    odometry: Optional[Pose3]
    raw: JsonObject = field(repr=False, compare=False)

    @staticmethod
    def from_json(m: JsonObject) -> "Pose":
        truth = Pose3.from_json(m["truth"]) if "truth" in m else None
        odometry = Pose3.from_json(m["odometry"]) if "odometry" in m else None
        return Pose(m["x"], m["y"], m["z"], m["roll"], m["pitch"], m["yaw"], m["stamp"], m["source"],
                    m.get("mode"), truth, odometry, m)


@dataclass(frozen=True)
class Status:
    """The 1 Hz status. The most asked-for fields are typed; everything else is in `raw`."""
    localization_state: str  # "ok", "degraded" or "lost"
    localization_reason: str  # for people, not for parsing
    map_version: int
    map_tiles: int
    clients: int
    scan_rate: float
    driver: str  # "simulator", "replay", "pcap" or "lidar"
    sensor_state: str  # "ok" or "stalled"
    scans: int  # scans the driver delivered
    raw: JsonObject = field(repr=False, compare=False)

    @staticmethod
    def from_json(m: JsonObject) -> "Status":
        return Status(m["localization"]["state"], m["localization"]["reason"], m["map"]["version"],
                      m["map"]["tiles"], m["clients"], m["scan_rate"], m["driver"]["kind"], m["sensor"]["state"],
                      m["sensor"]["scans"], m)


@dataclass(frozen=True)
class Relocalization:
    """The last search for the robot in a saved map: after a pose estimate (`set_pose`), or when it was lost."""
    stamp: float  # of the scan it searched with
    found: bool
    message: str  # where it was found, or why not ("two places fit as well ..."): for people, not for parsing

    @staticmethod
    def from_json(m: Optional[JsonObject]) -> Optional["Relocalization"]:
        return None if m is None else Relocalization(m["stamp"], m["found"], m["message"])


@dataclass(frozen=True)
class GoalState:
    """The current (or last) goal and its phase: accepted -> planning -> driving -> reached | failed | cancelled."""
    id: int  # 0: there has never been a goal
    phase: str
    x: Optional[float]
    y: Optional[float]
    z: Optional[float]
    reason: Optional[str]  # failed: why (goal_not_drivable, off_map, no_connection, blocked, ...); cancelled:
    # operator_disconnected or absent
    message: Optional[str]  # the same in words, as the server logs it: for people, not for parsing
    stamp: Optional[float]
    raw: JsonObject = field(repr=False, compare=False)

    @property
    def finished(self) -> bool:
        return self.phase in FINAL_GOAL_PHASES

    @staticmethod
    def from_json(m: JsonObject) -> "GoalState":
        return GoalState(m["id"], m["phase"], m.get("x"), m.get("y"), m.get("z"), m.get("reason"), m.get("message"),
                         m.get("stamp"), m)


@dataclass(frozen=True)
class Path:
    """The planned path, start to goal, map frame; z is the surface height. No points: no path."""
    goal_id: int
    version: int
    length: float
    points: tuple[tuple[float, float, float], ...]
    raw: JsonObject = field(repr=False, compare=False)

    @staticmethod
    def from_json(m: JsonObject) -> "Path":
        points = tuple((p[0], p[1], p[2]) for p in m["points"])
        return Path(m["goal_id"], m["version"], m["length"], points, m)


@dataclass(frozen=True)
class SavedMap:
    """One entry of GET /api/v1/maps."""
    name: str
    bytes: int
    modified: float  # s since the Unix epoch

    @staticmethod
    def from_json(m: JsonObject) -> "SavedMap":
        return SavedMap(m["name"], m["bytes"], m["modified"])


# The typed view of each server message that has one.
PARSERS = {
    "hello": Hello.from_json,
    "pose": Pose.from_json,
    "status": Status.from_json,
    "goal": GoalState.from_json,
    "path": Path.from_json,
}
