"""The binary frame layouts of proto/PROTOCOL.md, decoded from bytes built here by the documented layout."""

import struct

import pytest

from strata_client.frames import FrameError, OccupancyFrame, TileFrame, UnknownFrame, decode_frame, png_size


def header(kind: int, header_bytes: int, version: int = 7, stamp: float = 1.5) -> bytes:
    return struct.pack("<BBHIQd", kind, 1, header_bytes, 0, version, stamp)


def test_a_tile_frame_is_decoded_and_its_payload_handed_out_as_bytes():
    frame = decode_frame(header(1, 40) + struct.pack("<iiII", -3, 5, 12, 0) + b"DRACO-bytes")
    assert isinstance(frame, TileFrame)
    assert (frame.tile_x, frame.tile_y, frame.patches) == (-3, 5, 12)
    assert (frame.header.version, frame.header.stamp) == (7, 1.5)
    assert frame.draco == b"DRACO-bytes"
    assert not frame.removed


def test_an_empty_tile_payload_means_the_tile_is_gone():
    assert decode_frame(header(1, 40) + struct.pack("<iiII", 0, 0, 0, 0)).removed


def test_an_occupancy_frame_is_decoded():
    png = b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR" + struct.pack(">II", 3, 2) + b"\x08\x00\x00\x00"
    frame = decode_frame(header(2, 64) + struct.pack("<ddddII", -1.5, 2.5, 0.1, 0.4, 3, 2) + png)
    assert isinstance(frame, OccupancyFrame)
    assert (frame.origin_x, frame.origin_y, frame.resolution, frame.level_z) == (-1.5, 2.5, 0.1, 0.4)
    assert (frame.width, frame.height) == (3, 2)
    assert png_size(frame.png) == (3, 2)


def test_header_bytes_says_where_the_payload_starts():
    # A later layout version may append header fields; a client skips them.
    frame = decode_frame(header(1, 48) + struct.pack("<iiII", 1, 2, 3, 0) + b"newfield" + b"DRACO")
    assert frame.draco == b"DRACO"


def test_unknown_kinds_are_passed_on_and_broken_frames_refused():
    assert isinstance(decode_frame(header(9, 24) + b"x"), UnknownFrame)
    with pytest.raises(FrameError):
        decode_frame(b"\x01\x01")
    with pytest.raises(FrameError):
        decode_frame(header(1, 400))
    with pytest.raises(FrameError):
        decode_frame(header(1, 24))
