"""Exceptions the client raises. Server refusals carry the protocol's error code (proto/PROTOCOL.md "Errors")."""

from __future__ import annotations

from typing import Any, Optional

# The codes proto/PROTOCOL.md lists; programs branch on these, never on the message text.
ERROR_CODES = frozenset({
    "bad_json", "bad_message", "unknown_op", "bad_params", "unauthorized", "rate_limited", "not_found",
    "method_not_allowed", "bad_request", "forbidden", "unavailable", "corrupt_file", "io_error", "internal",
})


class StrataError(Exception):
    """The server refused something: `code` is the protocol's error code, `message` is for people."""

    def __init__(self, code: str, message: str, *, request: Optional[str] = None, request_id: Any = None,
                 http_status: Optional[int] = None) -> None:
        super().__init__(f"{code}: {message}" + (f" (request {request})" if request else ""))
        self.code = code
        self.message = message
        self.request = request  # the refused WebSocket op, when there was one
        self.request_id = request_id  # the refused message's id, when it had one
        self.http_status = http_status  # REST or refused upgrade: the HTTP status


class ProtocolVersionError(Exception):
    """The server speaks another major version of the protocol than this client."""


class ConnectionClosed(Exception):
    """The WebSocket connection closed (by us, the server or the network) while something waited on it."""


class GoalReplaced(Exception):
    """A newer goal (from this or another operator, or over REST) replaced the goal being waited for."""

    def __init__(self, goal_id: int, replaced_by: int) -> None:
        super().__init__(f"goal {goal_id} was replaced by goal {replaced_by}")
        self.goal_id = goal_id
        self.replaced_by = replaced_by
