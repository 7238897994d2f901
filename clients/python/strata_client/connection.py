"""The WebSocket /ws: one connection, a reader thread that dispatches every message, and requests answered by
`ack` or `error` (proto/PROTOCOL.md "WebSocket /ws")."""

from __future__ import annotations

import itertools
import json
import logging
import queue
import socket
import threading
import time
from typing import Any, Callable, Optional

import websocket

from .errors import ConnectionClosed, ProtocolVersionError, StrataError
from .frames import Frame, FrameError, OccupancyFrame, TileFrame, decode_frame
from .messages import PARSERS, GoalState, Hello, JsonObject

log = logging.getLogger("strata_client")

PROTOCOL_MAJOR = 1
SUBPROTOCOL = f"strata.v{PROTOCOL_MAJOR}"

# A refused upgrade answers a REST error body, which the WebSocket library does not hand out; its status
# names the code (proto/openapi.yaml, /ws).
_UPGRADE_STATUS_CODES = {400: "bad_request", 401: "unauthorized", 403: "forbidden", 404: "not_found",
                         503: "unavailable"}

# Called with ("received" | "sent", message) for every JSON message, and with the decoded frame for every
# binary one. Observers run on the reader thread (or the sender's): they must be quick and not block.
MessageObserver = Callable[[str, JsonObject], None]
FrameObserver = Callable[[Frame], None]
Listener = Callable[[Any], None]

_GOALS_KEPT = 64  # goal states remembered per connection, for Goal handles that wait


def check_protocol_version(protocol: Any, protocol_version: Any, where: str) -> None:
    """Refuses a server of another major version: its messages would not mean what this client expects."""
    if protocol_version != PROTOCOL_MAJOR or protocol != SUBPROTOCOL:
        raise ProtocolVersionError(
            f"{where}: the server speaks {protocol!r} (protocol version {protocol_version!r}); this client speaks "
            f"{SUBPROTOCOL!r}. Use a strata_client made for that protocol version.")


class Connection:
    def __init__(self, ws_url: str, token: Optional[str] = None, ca_file: Optional[str] = None,
                 timeout: float = 10.0) -> None:
        self.timeout = timeout
        header = [f"Authorization: Bearer {token}"] if token else []
        sslopt = {"ca_certs": ca_file} if ca_file else None
        try:
            # No Origin header: the server lets scripts (no Origin) in; only browsers' origins are checked.
            self._ws = websocket.create_connection(ws_url, timeout=timeout, subprotocols=[SUBPROTOCOL],
                                                   header=header, suppress_origin=True, sslopt=sslopt,
                                                   enable_multithread=True)
        except websocket.WebSocketBadStatusException as refused:
            status = refused.status_code
            code = _UPGRADE_STATUS_CODES.get(status, "internal")
            hint = " (wrong operator token)" if status == 401 else ""
            raise StrataError(code, f"the server refused the WebSocket upgrade with HTTP {status}{hint}",
                              http_status=status) from None
        except websocket.WebSocketException as refused:
            # websocket-client refuses a handshake answering another subprotocol than the one offered.
            raise ProtocolVersionError(f"WebSocket handshake with {ws_url} failed: {refused}") from None
        if self._ws.getsubprotocol() != SUBPROTOCOL:
            self._ws.close()
            raise ProtocolVersionError(f"the server answered subprotocol {self._ws.getsubprotocol()!r}, "
                                       f"not {SUBPROTOCOL!r}")

        # Reentrant: wait_until's conditions read the state through the same accessors other threads use.
        self._lock = threading.RLock()
        self._changed = threading.Condition(self._lock)
        self._closed = False
        self._close_reason: Optional[str] = None
        self._ids = itertools.count(1)
        self._pending: dict[str, "queue.Queue[JsonObject]"] = {}
        self._latest: dict[str, Any] = {}  # op -> typed message
        self._goals: dict[int, GoalState] = {}  # goal id -> its newest state
        self._max_goal_id = 0
        self._tiles: dict[tuple[int, int], TileFrame] = {}
        self._occupancy: Optional[OccupancyFrame] = None
        self._unanswered_errors: list[StrataError] = []  # errors for messages sent without an id
        self._listeners: dict[str, list[Listener]] = {}
        self._message_observers: list[MessageObserver] = []
        self._frame_observers: list[FrameObserver] = []
        # The server's clock (hello's and pong's clock_ms) minus ours at arrival, newest last: teleop's "t".
        self._clock_offsets: list[float] = []
        # One sequence for every teleop on this connection: the server refuses a moving one not above the last.
        self.teleop_sequence = itertools.count(1)

        # The first message is hello; read it before anything else so the role and version are known.
        self.hello = self._read_hello()
        self._ws.settimeout(None)  # the reader blocks until a message or the close
        self._reader = threading.Thread(target=self._read_loop, name="strata-ws-reader", daemon=True)
        self._reader.start()

    # --- observers and listeners -------------------------------------------------------------------------
    def add_message_observer(self, observer: MessageObserver) -> None:
        with self._lock:
            self._message_observers.append(observer)
        # The hello was read before anyone could observe it; observers see it too.
        observer("received", self.hello.raw)

    def add_frame_observer(self, observer: FrameObserver) -> None:
        with self._lock:
            self._frame_observers.append(observer)

    def on(self, kind: str, listener: Listener) -> Callable[[], None]:
        """Calls `listener` on the reader thread with each typed message of `kind` (an op such as "pose" or
        "goal"; "tile" and "occupancy" for frames; "message" for every JSON message as a dict; "error" for
        errors that answer messages sent without an id). Returns a function that removes it."""
        with self._lock:
            self._listeners.setdefault(kind, []).append(listener)

        def remove() -> None:
            with self._lock:
                if listener in self._listeners.get(kind, []):
                    self._listeners[kind].remove(listener)
        return remove

    # --- state -------------------------------------------------------------------------------------------
    @property
    def closed(self) -> bool:
        with self._lock:
            return self._closed

    def latest(self, op: str) -> Any:
        with self._lock:
            return self._latest.get(op)

    def tiles(self) -> dict[tuple[int, int], TileFrame]:
        with self._lock:
            return dict(self._tiles)

    def occupancy(self) -> Optional[OccupancyFrame]:
        with self._lock:
            return self._occupancy

    def max_goal_id(self) -> int:
        with self._lock:
            return self._max_goal_id

    def take_errors(self) -> list[StrataError]:
        """The errors that answered messages sent without an id (teleop's keep-alive), oldest first."""
        with self._lock:
            errors, self._unanswered_errors = self._unanswered_errors, []
            return errors

    def wait_until(self, condition: Callable[["Connection"], Any], timeout: float) -> Any:
        """Waits until `condition(self)` is truthy (checked after every message) and returns its value. Raises
        TimeoutError after `timeout` s and ConnectionClosed when the connection closes first."""
        deadline = time.monotonic() + timeout
        with self._changed:
            while True:
                value = condition(self)
                if value:
                    return value
                if self._closed:
                    raise ConnectionClosed(self._close_reason or "closed")
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    raise TimeoutError(f"nothing satisfied the condition within {timeout} s")
                self._changed.wait(remaining)

    def goal_state(self, goal_id: int) -> Optional[GoalState]:
        """Only from within a wait_until condition or with the lock held (the Goal handle's use)."""
        return self._goals.get(goal_id)

    def goal_states_after(self, goal_id: int) -> list[GoalState]:
        """Remembered goal states with ids above `goal_id`; for wait_until conditions."""
        return [state for key, state in sorted(self._goals.items()) if key > goal_id]

    def newest_goal_id(self) -> int:
        """For wait_until conditions: the highest goal id seen."""
        return self._max_goal_id

    # --- sending -----------------------------------------------------------------------------------------
    def send(self, message: JsonObject) -> None:
        """Sends a JSON message without waiting for an answer."""
        text = json.dumps(message, allow_nan=False)  # NaN is not JSON: refuse it here, not on the wire
        with self._lock:
            if self._closed:
                raise ConnectionClosed(self._close_reason or "closed")
            observers = list(self._message_observers)
        for observer in observers:
            observer("sent", message)
        try:
            self._ws.send(text)
        except (websocket.WebSocketException, OSError) as failure:
            raise ConnectionClosed(f"sending failed: {failure}") from None

    def request(self, message: JsonObject, timeout: Optional[float] = None) -> JsonObject:
        """Sends `message` with a fresh id and returns the `ack` (or `pong`) that answers it; an `error`
        answer raises StrataError with its code."""
        request_id = f"py-{next(self._ids)}"
        answer_queue: "queue.Queue[JsonObject]" = queue.Queue(maxsize=1)
        with self._lock:
            self._pending[request_id] = answer_queue
        try:
            self.send({**message, "id": request_id})
            try:
                answer = answer_queue.get(timeout=self.timeout if timeout is None else timeout)
            except queue.Empty:
                raise TimeoutError(f"no answer to {message.get('op')} within {timeout or self.timeout} s") from None
        finally:
            with self._lock:
                self._pending.pop(request_id, None)
        if answer.get("op") == "closed":
            raise ConnectionClosed(answer.get("reason", "closed"))
        if answer.get("op") == "error":
            raise StrataError(answer["code"], answer["message"], request=answer.get("request"),
                              request_id=answer.get("id"))
        return answer

    # --- closing -----------------------------------------------------------------------------------------
    def close(self) -> None:
        """Closes the connection and waits for the reader thread. Safe to call twice."""
        with self._lock:
            already = self._closed and not self._reader.is_alive()
        if not already:
            try:
                self._ws.send_close()  # the reader sees the server's close frame and ends
            except (websocket.WebSocketException, OSError):
                pass
            self._reader.join(2.0)
            if self._reader.is_alive() and self._ws.sock is not None:
                # No close frame came back: shutting the socket down wakes the reader's blocked recv.
                try:
                    self._ws.sock.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass
                self._reader.join(2.0)
        self._ws.shutdown()
        self._mark_closed("closed by the client")

    # --- the reader thread -------------------------------------------------------------------------------
    def _read_hello(self) -> Hello:
        try:
            opcode, data = self._ws.recv_data()
        except (websocket.WebSocketException, OSError) as failure:
            self._ws.shutdown()
            raise ConnectionClosed(f"no hello from the server: {failure}") from None
        message = json.loads(data) if opcode == websocket.ABNF.OPCODE_TEXT else None
        if not isinstance(message, dict) or message.get("op") != "hello":
            self._ws.shutdown()
            raise StrataError("bad_message", f"the first message was not hello: {data[:200]!r}")
        try:
            check_protocol_version(message.get("protocol"), message.get("protocol_version"), "hello")
        except ProtocolVersionError:
            self._ws.shutdown()
            raise
        hello = Hello.from_json(message)
        self._latest["hello"] = hello
        self._observe_server_clock(message)
        return hello

    def _observe_server_clock(self, message: JsonObject) -> None:
        clock_ms = message.get("clock_ms")
        if isinstance(clock_ms, (int, float)) and not isinstance(clock_ms, bool):
            with self._lock:
                self._clock_offsets = (self._clock_offsets + [clock_ms - time.monotonic() * 1000.0])[-8:]

    def server_clock_ms(self) -> Optional[float]:
        """The server's clock now, in ms, as told by hello and pong (proto/PROTOCOL.md, "Teleoperation"): each
        says the clock read at least clock_ms when it arrived, so the best estimate is the largest bound
        over the last eight. None from a server before protocol 1.1."""
        with self._lock:
            if not self._clock_offsets:
                return None
            return time.monotonic() * 1000.0 + max(self._clock_offsets)

    def _read_loop(self) -> None:
        reason = "closed by the server"
        try:
            while True:
                opcode, data = self._ws.recv_data()
                if opcode == websocket.ABNF.OPCODE_TEXT:
                    self._dispatch_text(data.decode("utf-8") if isinstance(data, bytes) else data)
                elif opcode == websocket.ABNF.OPCODE_BINARY:
                    self._dispatch_frame(data)
                elif opcode == websocket.ABNF.OPCODE_CLOSE:
                    break
        except (websocket.WebSocketException, OSError) as failure:
            reason = f"connection lost: {failure}"
        except Exception:  # a bug here must not leave waiters hanging
            log.exception("strata_client: the reader thread failed")
            reason = "the reader thread failed"
        self._mark_closed(reason)

    def _mark_closed(self, reason: str) -> None:
        with self._changed:
            if self._closed:
                return
            self._closed = True
            self._close_reason = reason
            pending = list(self._pending.values())
            self._changed.notify_all()
        for answer_queue in pending:
            try:
                answer_queue.put_nowait({"op": "closed", "reason": reason})
            except queue.Full:
                pass

    def _dispatch_text(self, text: str) -> None:
        message = json.loads(text)
        if not isinstance(message, dict) or not isinstance(message.get("op"), str):
            log.warning("strata_client: ignoring a text frame that is not a message: %.200s", text)
            return
        op = message["op"]
        if op == "pong":
            self._observe_server_clock(message)
        parser = PARSERS.get(op)
        typed = parser(message) if parser else message  # ops this client does not know are kept as dicts
        answer_queue = None
        with self._changed:
            observers = list(self._message_observers)
            calls: list[tuple[Listener, Any]] = [(listener, typed) for listener in self._listeners.get(op, [])]
            calls += [(listener, message) for listener in self._listeners.get("message", [])]
            if op in ("ack", "error", "pong") and isinstance(message.get("id"), str):
                answer_queue = self._pending.get(message["id"])
            if op == "error" and answer_queue is None:
                error = StrataError(message["code"], message["message"], request=message.get("request"),
                                    request_id=message.get("id"))
                self._unanswered_errors = (self._unanswered_errors + [error])[-100:]
                calls += [(listener, error) for listener in self._listeners.get("error", [])]
            if parser:
                self._latest[op] = typed
            if isinstance(typed, GoalState):
                self._goals[typed.id] = typed
                self._max_goal_id = max(self._max_goal_id, typed.id)
                for old in sorted(self._goals)[:-_GOALS_KEPT]:
                    del self._goals[old]
            self._changed.notify_all()
        for observer in observers:
            observer("received", message)
        if answer_queue is not None:
            answer_queue.put_nowait(message)
        for listener, value in calls:
            self._call(listener, value)

    def _dispatch_frame(self, data: bytes) -> None:
        try:
            frame = decode_frame(data)
        except FrameError as bad:
            log.warning("strata_client: ignoring a binary frame: %s", bad)
            return
        kind = {TileFrame: "tile", OccupancyFrame: "occupancy"}.get(type(frame))
        with self._changed:
            observers = list(self._frame_observers)
            listeners = list(self._listeners.get(kind, [])) if kind else []
            if isinstance(frame, TileFrame):
                if frame.removed:
                    self._tiles.pop(frame.key, None)
                else:
                    self._tiles[frame.key] = frame
            elif isinstance(frame, OccupancyFrame):
                self._occupancy = frame
            self._changed.notify_all()
        for observer in observers:
            observer(frame)
        for listener in listeners:
            self._call(listener, frame)

    @staticmethod
    def _call(listener: Listener, value: Any) -> None:
        try:
            listener(value)
        except Exception:  # a listener's bug must not stop the stream for everyone else
            log.exception("strata_client: a listener failed")
