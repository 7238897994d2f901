"""A Python client for the Strata map server (protocol strata.v1, proto/PROTOCOL.md)."""

from .client import StrataClient, connect
from .connection import PROTOCOL_MAJOR, SUBPROTOCOL
from .errors import ConnectionClosed, GoalReplaced, ProtocolVersionError, StrataError
from .frames import FrameHeader, OccupancyFrame, TileFrame, decode_frame
from .goals import Goal, GoalOutcome
from .messages import GoalState, Hello, Path, Pose, Pose3, Relocalization, SavedMap, ServerInfo, Status
from .rest import OccupancyImage
from .teleop import Teleop

__version__ = "0.1.0"

__all__ = [
    "StrataClient", "connect", "PROTOCOL_MAJOR", "SUBPROTOCOL", "ConnectionClosed", "GoalReplaced",
    "ProtocolVersionError", "StrataError", "FrameHeader", "OccupancyFrame", "TileFrame", "decode_frame", "Goal",
    "GoalOutcome", "GoalState", "Hello", "Path", "Pose", "Pose3", "Relocalization", "SavedMap", "ServerInfo", "Status",
    "OccupancyImage", "Teleop",
]
