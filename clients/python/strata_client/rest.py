"""The REST API under /api/v1 (proto/openapi.yaml) over one requests session."""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import Any, Callable, Optional
from urllib.parse import urlsplit, urlunsplit

import requests

from .errors import StrataError
from .frames import TileFrame, decode_frame
from .messages import GoalState, Path, Pose, ServerInfo, Status

# Called with (method, path, HTTP status, JSON body or None) for every answer: the API tests check the
# bodies against proto/schemas/rest/.
ResponseObserver = Callable[[str, str, int, Any], None]


def http_base_url(url: str) -> str:
    """The server's http(s)://host:port from any URL naming it (http, https, ws, wss; a path is dropped)."""
    parts = urlsplit(url if "://" in url else "http://" + url)
    scheme = {"ws": "http", "wss": "https"}.get(parts.scheme, parts.scheme)
    if scheme not in ("http", "https"):
        raise ValueError(f"not a strata server URL: {url!r} (expected http://, https://, ws:// or wss://)")
    if not parts.netloc:
        raise ValueError(f"no host in the URL {url!r}")
    return urlunsplit((scheme, parts.netloc, "", "", ""))


@dataclass(frozen=True)
class OccupancyImage:
    """GET /api/v1/occupancy: the drivable map at the robot's level and where it lies."""
    png: bytes
    origin_x: float
    origin_y: float
    resolution: float
    level_z: float
    version: int


class RestClient:
    def __init__(self, url: str, token: Optional[str] = None, ca_file: Optional[str] = None,
                 timeout: float = 10.0) -> None:
        self.base_url = http_base_url(url)
        self.timeout = timeout
        self._token = token
        self._session = requests.Session()
        # A CA file verifies a server with its own certificate (https); otherwise the system's CAs. Given per
        # request: requests lets REQUESTS_CA_BUNDLE override the session's setting, but not the request's.
        self._verify = ca_file if ca_file else None
        self._observers: list[ResponseObserver] = []
        self._observers_lock = threading.Lock()

    def add_observer(self, observer: ResponseObserver) -> None:
        with self._observers_lock:
            self._observers.append(observer)

    def close(self) -> None:
        self._session.close()

    def request(self, method: str, path: str, *, json_body: Any = None, operator: bool = False,
                params: Optional[dict[str, str]] = None) -> requests.Response:
        """Sends a request; answers 4xx/5xx become StrataError with the body's error code."""
        headers = {}
        # Without a token the request still goes out: the server's refusal (401 unauthorized) is the answer.
        if operator and self._token:
            headers["Authorization"] = f"Bearer {self._token}"
        response = self._session.request(method, self.base_url + path, json=json_body, params=params,
                                         headers=headers, timeout=self.timeout, verify=self._verify)
        body = _json_or_none(response)
        with self._observers_lock:
            observers = list(self._observers)
        for observer in observers:
            observer(method, path, response.status_code, body)
        if response.status_code >= 400:
            error = body.get("error") if isinstance(body, dict) else None
            if isinstance(error, dict) and "code" in error:
                raise StrataError(error["code"], error.get("message", ""), http_status=response.status_code)
            raise StrataError("internal", f"{method} {path}: HTTP {response.status_code} without an error body",
                              http_status=response.status_code)
        return response

    def get_json(self, path: str, *, operator: bool = False) -> Any:
        return self.request("GET", path, operator=operator).json()

    def healthz(self) -> bool:
        return self.get_json("/healthz").get("status") == "ok"

    def info(self) -> ServerInfo:
        return ServerInfo.from_json(self.get_json("/api/v1/info"))

    def pose(self) -> Pose:
        return Pose.from_json(self.get_json("/api/v1/pose"))

    def status(self) -> Status:
        return Status.from_json(self.get_json("/api/v1/status"))

    def goal(self) -> GoalState:
        return GoalState.from_json(self.get_json("/api/v1/goal"))

    def path(self) -> Path:
        return Path.from_json(self.get_json("/api/v1/path"))

    def set_goal(self, x: float, y: float, z: Optional[float] = None) -> GoalState:
        """A goal without a connection: it runs until reached, failed, replaced or cancelled."""
        body: dict[str, float] = {"x": x, "y": y}
        if z is not None:
            body["z"] = z
        return GoalState.from_json(self.request("POST", "/api/v1/goal", json_body=body, operator=True).json())

    def cancel_goal(self) -> GoalState:
        return GoalState.from_json(self.request("DELETE", "/api/v1/goal", operator=True).json())

    def occupancy(self) -> OccupancyImage:
        response = self.request("GET", "/api/v1/occupancy")
        origin_x, origin_y = (float(v) for v in response.headers["X-Strata-Origin"].split(","))
        return OccupancyImage(response.content, origin_x, origin_y, float(response.headers["X-Strata-Resolution"]),
                              float(response.headers["X-Strata-Level"]), int(response.headers["X-Strata-Version"]))

    def tile_index(self) -> dict[str, Any]:
        """GET /api/v1/tiles: {"version": ..., "tiles": [{"x", "y", "version", "patches", "bytes", "etag"}]}."""
        return self.get_json("/api/v1/tiles")

    def tile(self, tile_x: int, tile_y: int) -> TileFrame:
        frame = decode_frame(self.request("GET", f"/api/v1/tiles/{int(tile_x)}/{int(tile_y)}").content)
        if not isinstance(frame, TileFrame):
            raise StrataError("internal", f"/api/v1/tiles/{tile_x}/{tile_y} did not answer a tile frame")
        return frame

    def metrics(self) -> str:
        return self.request("GET", "/metrics").text


def _json_or_none(response: requests.Response) -> Any:
    if "json" not in response.headers.get("Content-Type", ""):
        return None
    try:
        return response.json()
    except ValueError:
        return None
