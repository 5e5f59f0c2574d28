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
    """A command header word (hls/frame_format.hpp): opcode [31:29], region [28:24], count."""
    return (op << 29) | (region << 24) | (count & 0xFFFFFF)


WRITE, RUN, READ, STATUS = 1, 2, 3, 4


def write(name, data):
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(data)


hello = frame(HELLO, 0, words(1, 1, 1 << 20))
status = words(header(STATUS, 0, 1))
write_state = words(header(WRITE, 1, 1), 0, 1, 2, 3, 4, 5, 6)  # one particle: x[3], p[3]
run = words(header(RUN, 0, 2), 0x100, 0x200)                   # two steps, two plate words
read = words(header(READ, 1, 2), 0)                            # two particles from index 0

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

# Attacks on the server's limits (frame_budget.hpp, docs/input-limits.md "Servers"): the harness
# serves each stream with the null core, the host hanging up or a stop request (a signal)
# arriving after its last byte, mid-command in a long one.
# One READ of 2^24 - 1 material entries: 117 M response words, 8 bytes of command.
write("huge_read", hello + frame(COMMAND, 1, words(header(READ, 4, 0xFFFFFF), 0)))
# 64 READs of 65,536 edge lengths: each within the limit, 4 M response words together.
write("many_reads", hello + frame(COMMAND, 1, words(*[w for _ in range(64)
                                                     for w in (header(READ, 5, 0x10000), 0)])))
# A READ whose index word comes in the next frame: its answer counts there.
write("read_split_over_frames", hello + frame(COMMAND, 1, words(header(READ, 4, 0xFFFFFF))) +
      frame(COMMAND, 2, words(0)))
# One step more than a frame may run.
write("too_many_steps", hello + frame(COMMAND, 1, words(header(RUN, 0, 4097), *range(4097))))
# A long RUN within the limits; the harness ends an even-length input with the host hanging
# up and an odd-length one with a stop request (a signal): here in the RUN's middle.
long_run = hello + frame(COMMAND, 1, words(header(RUN, 0, 1000), *range(1000)))
write("long_run_then_hang_up", long_run)
write("long_run_then_signal", long_run + b"\x00")  # a stray byte after the frame: odd length
