"""A goal set over the WebSocket, followed on the goal stream until it is reached, fails or is cancelled."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

from .errors import GoalReplaced
from .messages import GoalState

if TYPE_CHECKING:
    from .connection import Connection

COORDINATE_LIMIT = 1_000_000.0  # proto/schemas/ws-client/set_goal.schema.json
_SAME_COORDINATE = 1e-6  # the goal stream echoes the coordinates sent; JSON round trips keep them


def check_coordinate(name: str, value: float) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"goal {name} must be a number, not {type(value).__name__}")
    if not math.isfinite(value):
        raise ValueError(f"goal {name} must be finite, not {value}")
    if abs(value) > COORDINATE_LIMIT:
        raise ValueError(f"goal {name} = {value} is beyond the protocol's +-{COORDINATE_LIMIT:g} m")
    return float(value)


@dataclass(frozen=True)
class GoalOutcome:
    """How a goal ended: phase reached, failed (with the reason, e.g. goal_not_drivable) or cancelled."""
    goal_id: int
    phase: str
    reason: Optional[str]
    state: GoalState

    @property
    def reached(self) -> bool:
        return self.phase == "reached"

    @property
    def message(self) -> Optional[str]:
        """Why it failed or was cancelled, in words (for people; `reason` is for programs)."""
        return self.state.message


class Goal:
    """The handle `set_goal` returns. The server numbers goals; this handle learns its goal's number from the
    first goal message after the set_goal's ack that names the same coordinates."""

    def __init__(self, connection: "Connection", x: float, y: float, z: Optional[float], after_id: int) -> None:
        self._connection = connection
        self.x, self.y, self.z = x, y, z
        self._after_id = after_id  # the newest goal id before this one was set
        self._id: Optional[int] = None

    def _matches(self, state: GoalState) -> bool:
        def same(a: Optional[float], b: Optional[float]) -> bool:
            return (a is None and b is None) or (a is not None and b is not None and abs(a - b) < _SAME_COORDINATE)
        return same(state.x, self.x) and same(state.y, self.y) and same(state.z, self.z)

    def _find_id(self, connection: "Connection") -> Optional[int]:
        if self._id is None:
            for state in connection.goal_states_after(self._after_id):
                if self._matches(state):
                    self._id = state.id
                    break
        return self._id

    @property
    def id(self) -> int:
        """The server's goal id; waits (the client's timeout) for the goal stream to name it."""
        return self._connection.wait_until(self._find_id, self._connection.timeout)

    @property
    def state(self) -> GoalState:
        """The newest state of this goal the goal stream reported."""
        goal_id = self.id
        return self._connection.wait_until(lambda c: c.goal_state(goal_id), self._connection.timeout)

    def wait(self, timeout: float = 120.0, phases: frozenset[str] = frozenset({"reached", "failed", "cancelled"})
             ) -> GoalOutcome:
        """Waits (at most `timeout` s of wall time) until the goal's phase is one of `phases` (by default: it
        ended) and returns the outcome; raises GoalReplaced when a newer goal replaced it first, TimeoutError,
        or ConnectionClosed (which cancels a goal set over the WebSocket)."""
        def ended(connection: "Connection") -> Optional[GoalState]:
            goal_id = self._find_id(connection)
            if goal_id is None:
                return None
            state = connection.goal_state(goal_id)
            if state is not None and state.phase in phases:
                return state
            newest = connection.newest_goal_id()
            if newest > goal_id:
                raise GoalReplaced(goal_id, newest)
            return None

        state: GoalState = self._connection.wait_until(ended, timeout)
        return GoalOutcome(state.id, state.phase, state.reason, state)

    def __repr__(self) -> str:
        return f"Goal(id={self._id}, x={self.x}, y={self.y}, z={self.z})"
