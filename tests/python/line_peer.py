"""A Modbus RTU master on serial port 1's pseudo-terminal with the line settings it is
given, as a master on a real RS-485 line would have them (pyserial).

    python line_peer.py LINK FRAME [inpck]

FRAME is data bits, parity, stop bits: 8N1, 8E1, 8O1, 8N2. With `inpck` the master also
turns on input parity checking (termios INPCK), as libmodbus does with parity on. It reads
the run speed (0x6B03) of station 1 at 38400 baud and prints `answered` (the right answer),
or `silent` (nothing within 1 s); anything else exits non-zero.
"""
import sys
import termios

import serial
from pymodbus.framer.rtu import FramerRTU

link, frame = sys.argv[1], sys.argv[2]
data_bits, parity, stop_bits = int(frame[0]), frame[1], int(frame[2])
inpck = sys.argv[3:] == ["inpck"]
# With `inpck` the parity is set with INPCK in one call, as libmodbus does: pyserial alone
# would set PARENB, which a pseudo-terminal drops.
port = serial.Serial(link, 38400, bytesize=data_bits, parity="N" if inpck else parity, stopbits=stop_bits, timeout=1)
if inpck:
    attrs = termios.tcgetattr(port.fd)
    attrs[0] |= termios.INPCK
    attrs[2] |= termios.PARENB | (termios.PARODD if parity == "O" else 0)
    termios.tcsetattr(port.fd, termios.TCSANOW, attrs)


def crc16(data):
    """The frame's two CRC bytes in line order, as pymodbus computes them."""
    return FramerRTU.compute_CRC(data).to_bytes(2, "big")


read = bytes([1, 0x03, 0x6B, 0x03, 0x00, 0x01])
answer = bytes([1, 0x03, 0x02, 0x00, 100])
port.write(read + crc16(read))
got = port.read(len(answer) + 2)
if got == answer + crc16(answer):
    print("answered")
elif not got:
    print("silent")
else:
    sys.exit(f"an answer that is no frame: {got!r}")
