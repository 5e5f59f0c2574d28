#!/usr/bin/env python3
"""Writes the seed corpus of fuzz_link_frame (fuzz/corpus/fuzz_link_frame/): byte streams
of link frames as host/driver/link/link_frame.hpp lays them out, valid sessions and the
near-misses the parser must refuse. Rerun after a change of the frame format; the files
are checked in so that the fuzzers need no Python."""
import os
import struct
import zlib

MAGIC = 0x4B4C4852
HELLO, COMMAND, RESPONSE, ERROR, SHUTDOWN = 1, 2, 3, 4, 5
OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus", "fuzz_link_frame")


def frame(ftype, seq, payload=b"", version=1, reserved=0, length=None, crc=None):
    header = struct.pack("<IBBHII", MAGIC, version, ftype, reserved, seq,
                         len(payload) if length is None else length)
    body = header + payload
    return body + struct.pack("<I", zlib.crc32(body) if crc is None else crc)


def words(*ws):
    return struct.pack("<%dI" % len(ws), *ws)


def header(op, region, count):
    return (op << 28) | (region << 24) | (count & 0xFFFFFF)


def write(name, data):
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)


hello = frame(HELLO, 0, words(1, 1, 1 << 20))
status = words(header(4, 0, 1))
write_state = words(header(1, 1, 1), 0, 1, 2, 3, 4, 5, 6)  # one particle: x[3], p[3]
run = words(header(2, 0, 2), 0x100, 0x200)                 # two steps, two plate words
read = words(header(3, 1, 2), 0)                           # two particles from index 0

write("hello", hello)
write("host_session", hello + frame(COMMAND, 1, write_state + run) +
      frame(COMMAND, 2, read + status) + frame(SHUTDOWN, 3))
write("device_session", hello + frame(RESPONSE, 1, words(7, 8)) +
      frame(RESPONSE, 2, words(*range(12))) + frame(RESPONSE, 3, words(0, 5, 100, 1)))
write("error_text", hello + frame(ERROR, 1, b"core: sticky overflow flags 0x3"))
write("empty_command", frame(COMMAND, 0))
write("bad_crc", frame(COMMAND, 0, status, crc=0xDEADBEEF))
write("bad_version", frame(HELLO, 0, words(1, 1, 4096), version=2))
write("bad_type", frame(9, 0))
write("reserved_set", frame(COMMAND, 0, status, reserved=1))
write("sequence_gap", hello + frame(COMMAND, 2, status))
write("oversized", frame(COMMAND, 0, b"", length=(1 << 20) + 4)[:16])
write("odd_words", frame(COMMAND, 0, b"\x01\x02\x03"))
write("truncated", (hello + frame(COMMAND, 1, write_state))[:-7])
write("garbage_after_frame", hello + b"RHLX\x01\x02\x00\x00")
write("bad_opcode", frame(COMMAND, 0, words(header(7, 0, 1))))
