"""Decoding the server's binary frames (proto/PROTOCOL.md "Binary frames"): map tiles and the occupancy PNG.

The tile payload is a Draco point set (proto/TILE_ENCODING.md); it is handed out as bytes, undecoded, so this
package needs no Draco binding.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from typing import Union

KIND_TILE = 1
KIND_OCCUPANCY = 2

# Every frame starts with this little-endian header: kind, layout version, header_bytes, reserved,
# map version, stamp.
_COMMON = struct.Struct("<BBHIQd")
_TILE = struct.Struct("<iiII")  # tile_x, tile_y, patches, reserved; at offset 24
_OCCUPANCY = struct.Struct("<ddddII")  # origin_x, origin_y, resolution, level_z, width, height; at offset 24

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


class FrameError(ValueError):
    """A binary frame too short for its header or with a header that contradicts itself."""


@dataclass(frozen=True)
class FrameHeader:
    kind: int
    layout_version: int
    header_bytes: int
    version: int  # the map version of the tile or image
    stamp: float  # wall-clock time of the scan behind this data, s since the Unix epoch; 0: unknown


@dataclass(frozen=True)
class TileFrame:
    header: FrameHeader
    tile_x: int
    tile_y: int
    patches: int
    draco: bytes  # one Draco point per patch (TILE_ENCODING.md); empty: the tile is gone

    @property
    def key(self) -> tuple[int, int]:
        return (self.tile_x, self.tile_y)

    @property
    def removed(self) -> bool:
        return not self.draco


@dataclass(frozen=True)
class OccupancyFrame:
    header: FrameHeader
    origin_x: float  # map-frame x of the image's left edge, m
    origin_y: float  # map-frame y of the image's bottom edge, m
    resolution: float  # m per pixel
    level_z: float  # ground height of the patch the robot stands on, m
    width: int
    height: int
    png: bytes  # 8-bit grey: free 254, occupied 0, unknown 205; row 0 is the highest y


@dataclass(frozen=True)
class UnknownFrame:
    """A frame kind this client does not know: the protocol says to ignore it, so it is only passed on."""
    header: FrameHeader
    data: bytes


Frame = Union[TileFrame, OccupancyFrame, UnknownFrame]


def decode_frame(data: bytes) -> Frame:
    if len(data) < _COMMON.size:
        raise FrameError(f"binary frame of {len(data)} bytes is shorter than the {_COMMON.size}-byte header")
    kind, layout_version, header_bytes, _reserved, version, stamp = _COMMON.unpack_from(data, 0)
    header = FrameHeader(kind, layout_version, header_bytes, version, stamp)
    if header_bytes > len(data):
        raise FrameError(f"header_bytes {header_bytes} exceeds the frame's {len(data)} bytes")
    # header_bytes, not the layout we know, says where the payload starts: a later layout may add fields.
    payload = bytes(data[header_bytes:])
    if kind == KIND_TILE:
        if header_bytes < _COMMON.size + _TILE.size:
            raise FrameError(f"tile frame header of {header_bytes} bytes is too short")
        tile_x, tile_y, patches, _ = _TILE.unpack_from(data, _COMMON.size)
        return TileFrame(header, tile_x, tile_y, patches, payload)
    if kind == KIND_OCCUPANCY:
        if header_bytes < _COMMON.size + _OCCUPANCY.size:
            raise FrameError(f"occupancy frame header of {header_bytes} bytes is too short")
        origin_x, origin_y, resolution, level_z, width, height = _OCCUPANCY.unpack_from(data, _COMMON.size)
        return OccupancyFrame(header, origin_x, origin_y, resolution, level_z, width, height, payload)
    return UnknownFrame(header, payload)


def png_size(png: bytes) -> tuple[int, int]:
    """Width and height from a PNG's IHDR chunk, to check an image against its frame without an image library."""
    if len(png) < 24 or not png.startswith(PNG_MAGIC) or png[12:16] != b"IHDR":
        raise FrameError("not a PNG")
    width, height = struct.unpack_from(">II", png, 16)
    return width, height
