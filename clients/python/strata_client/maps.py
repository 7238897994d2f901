"""Saving, loading, listing and downloading maps over REST (operator: save, load; anyone: list, download)."""

from __future__ import annotations

import os
import re
from typing import Union
from urllib.parse import quote

from .messages import SavedMap
from .rest import RestClient

# The protocol's map-name rule (proto/schemas/ws-client/save_map.schema.json): a file name, never a path.
MAP_NAME = re.compile(r"[A-Za-z0-9_-][A-Za-z0-9._-]{0,63}")
MAP_FORMATS = ("strata", "ply", "pgm", "yaml")


def check_map_name(name: str) -> str:
    if not isinstance(name, str) or not MAP_NAME.fullmatch(name):
        raise ValueError(f"map name {name!r}: 1-64 characters of A-Z a-z 0-9 . _ -, not starting with a dot")
    return name


class Maps:
    def __init__(self, rest: RestClient) -> None:
        self._rest = rest

    def list(self) -> list[SavedMap]:
        """The maps directory's maps that can be loaded."""
        return [SavedMap.from_json(m) for m in self._rest.get_json("/api/v1/maps")["maps"]]

    def save(self, name: str) -> None:
        """Saves the current map under `name` in the server's maps directory (atomic on the server)."""
        self._rest.request("POST", "/api/v1/maps", json_body={"name": check_map_name(name)}, operator=True)

    def load(self, name: str, mode: str = "mapping") -> str:
        """Replaces the current map by a saved one, for "mapping" (the scans go on into it) or to "localize"
        in it (it is fixed). Returns the server's note on the load (an older file loads for viewing only);
        raises StrataError not_found, corrupt_file, or bad_params (a file without localization data)."""
        if mode not in ("mapping", "localize"):
            raise ValueError(f"map mode {mode!r}: mapping or localize")
        response = self._rest.request(
            "POST", f"/api/v1/maps/{quote(check_map_name(name))}/load", json_body={"mode": mode}, operator=True
        )
        return response.json().get("message", "")

    def download(self, fmt: str = "strata") -> bytes:
        """The current map: strata (native), ply (patches as points), pgm or yaml (ROS map_server)."""
        if fmt not in MAP_FORMATS:
            raise ValueError(f"map format {fmt!r}: one of {', '.join(MAP_FORMATS)}")
        return self._rest.request("GET", "/api/v1/map", params={"format": fmt}).content

    def download_to(self, path: Union[str, os.PathLike], fmt: str = "strata") -> int:
        data = self.download(fmt)
        with open(path, "wb") as out:
            out.write(data)
        return len(data)
