"""The far end of luamotion's serial port 1 in tests/serial.rs: pyserial on the
pseudo-terminal (through the link the controller makes). Exits non-zero with a reason
when the controller's side does not behave.

    python serial_peer.py LINK frames     FreePort frames, bad input, a wrong line
    python serial_peer.py LINK stop       the handshake, 1 s, then sends "stop"
    python serial_peer.py LINK rtu        Modbus RTU frames with bad CRCs and garbage
    python serial_peer.py LINK ascii      Modbus ASCII frames, one with a bad LRC

A third argument `late` opens the line 1 s after it appears, as a peer on a loaded
machine may.
"""
import os
import sys
import time

import serial

link, scenario = sys.argv[1], sys.argv[2]
deadline = time.time() + 30
while not os.path.exists(link):
    if time.time() > deadline:
        sys.exit(f"{link} never appeared")
    time.sleep(0.01)
if sys.argv[3:] == ["late"]:
    time.sleep(1.0)
port = serial.Serial(link, 38400, timeout=10)  # 8,N,1


def expect(data):
    got = port.read(len(data))
    if got != data:
        sys.exit(f"expected {data!r}, got {got!r}")


def handshake():
    """pyserial's open() flushes the line's input (serialposix.Serial.open), so a READY
    the program sent before it loses: the program says READY until it hears go, then
    GO, after which nothing of the handshake comes."""
    seen = b""
    answered = False
    while not seen.endswith(b":GO\r\n"):
        byte = port.read(1)
        if not byte:
            sys.exit(f"no GO from the program; last bytes {seen[-64:]!r}")
        seen += byte
        if not answered and seen.endswith(b":READY\r\n"):
            port.write(b":go\r\n")
            answered = True


def crc16(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ 0xA001 if crc & 1 else crc >> 1
    return crc.to_bytes(2, "little")


if scenario == "frames":
    handshake()
    port.write(b":one\r\n:two\r\n")  # two frames in one write
    port.write(b":spl")  # one frame in two writes
    port.flush()
    time.sleep(0.1)
    port.write(b"it\r\n")
    port.write(b":" + b"x" * 300 + b"\r\n")  # too long
    port.write(b":after long\r\n")
    port.write(bytes(b for b in range(256) if b not in b":\r\n")[:200])  # no start, no end
    port.write(b":good\r\n")
    expect(b"".join(b":ack %d\r\n" % n for n in range(1, 6)))
    # A peer set to another baud rate: its bytes are a line error, not data.
    port.baudrate = 9600
    port.write(b":wrong\r\n")
    expect(b":line error\r\n")
    port.baudrate = 38400
    port.write(b":END\r\n")
elif scenario == "stop":
    handshake()
    time.sleep(1.0)
    port.write(b":stop\r\n")
elif scenario == "rtu":
    port.timeout = 0.5
    read = bytes([1, 0x03, 0x6B, 0x03, 0x00, 0x01])  # the run speed, 100 %
    answer = bytes([1, 0x03, 0x02, 0x00, 100])
    answer += crc16(answer)
    bad = read + bytes(b ^ 0xFF for b in crc16(read))
    port.write(bad)
    got = port.read(1)
    if got:
        sys.exit(f"a frame with a wrong CRC was answered: {got!r}")
    port.write(bytes([0xDE, 0xAD, 0xBE, 0xEF, 0x03, 0x10]) + read + crc16(read))
    expect(answer)
    port.write(read + crc16(read))
    expect(answer)
    # For another station: no answer.
    other = bytes([7]) + read[1:]
    port.write(other + crc16(other))
    got = port.read(1)
    if got:
        sys.exit(f"a frame for station 7 was answered: {got!r}")
elif scenario == "ascii":
    port.timeout = 0.5

    def ascii_frame(data):
        lrc = (-sum(data)) & 0xFF
        return b":" + (data + bytes([lrc])).hex().upper().encode() + b"\r\n"

    read = bytes([1, 0x03, 0x6B, 0x03, 0x00, 0x01])  # the run speed, 100 %
    port.write(ascii_frame(read)[:-5] + b"00\r\n")  # a wrong LRC
    got = port.read(1)
    if got:
        sys.exit(f"a frame with a wrong LRC was answered: {got!r}")
    port.write(b"noise" + ascii_frame(read))
    expect(ascii_frame(bytes([1, 0x03, 0x02, 0x00, 100])))
else:
    sys.exit(f"no scenario {scenario}")
