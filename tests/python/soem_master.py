"""SOEM (through pysoem) as the master of `luamotion subdevices` on the other end of a
wire: scan, SDOs, DC, mapping, Op, and a CSP loop at 1 ms that enables the first drive and
moves it 10 mm. Prints what it found as one JSON object; tests/subdevices.rs judges it.

usage: soem_master.py INTERFACE COUNTS_PER_MM
"""

import json
import math
import struct
import sys
import time

import pysoem

CYCLE_NS = 1_000_000
FOLLOWING_ERROR_WINDOW = 10_000  # counts: 1 mm at 10 000 counts/mm
FOLLOWING_ERROR_TIMEOUT_MS = 10


def u32(data):
    return int.from_bytes(data, "little")


def abort_of(call):
    """The SDO abort code a call ends with, or None when it succeeded."""
    try:
        call()
    except pysoem.SdoError as error:
        return error.abort_code
    return None


def every_ms(cycles, body):
    """Runs body(k) once per ms for `cycles` ms on the monotonic clock."""
    start = time.monotonic_ns()
    for k in range(cycles):
        body(k)
        deadline = start + (k + 1) * CYCLE_NS
        while time.monotonic_ns() < deadline:
            left = deadline - time.monotonic_ns()
            if left > 200_000:
                time.sleep((left - 150_000) / 1e9)


def main():
    interface, counts_per_mm = sys.argv[1], float(sys.argv[2])
    report = {}
    master = pysoem.Master()
    master.open(interface)
    report["count"] = master.config_init()
    slaves = master.slaves
    report["identity"] = [[s.man, s.id, s.rev] for s in slaves]
    report["names"] = [s.name for s in slaves]
    master.read_state()
    report["after_init"] = [s.state for s in slaves]

    first = slaves[0]
    report["sdo"] = {
        "0x1000": u32(first.sdo_read(0x1000, 0)),
        "0x1018": [u32(first.sdo_read(0x1018, sub)) for sub in range(1, 5)],
        "0x6060": struct.unpack("<b", first.sdo_read(0x6060, 0))[0],
        "0x6502": u32(first.sdo_read(0x6502, 0)),
    }
    report["abort_missing"] = abort_of(lambda: first.sdo_read(0x6011, 0))
    report["abort_read_only"] = abort_of(lambda: first.sdo_write(0x1018, 1, struct.pack("<I", 1)))

    # The second variant: raw FPRD of the AL status, and EEPROM reads by word.
    report["al_status_fprd"] = [struct.unpack("<H", s._fprd(0x0130, 2))[0] for s in slaves]
    report["eeprom"] = [[u32(s.eeprom_read(word)) for word in (0x08, 0x0A, 0x0C, 0x18, 0x1C)] for s in slaves]

    report["dc"] = master.config_dc()
    for s in slaves:
        s.sdo_write(0x1C32, 2, struct.pack("<I", CYCLE_NS))
        s.sdo_write(0x6065, 0, struct.pack("<I", FOLLOWING_ERROR_WINDOW))
        s.sdo_write(0x6066, 0, struct.pack("<H", FOLLOWING_ERROR_TIMEOUT_MS))
        s.dc_sync(True, CYCLE_NS)
    report["image"] = master.config_map()
    report["safe_op"] = master.state_check(pysoem.SAFEOP_STATE, 2_000_000)
    master.read_state()
    report["after_map"] = [s.state for s in slaves]
    report["expected_wkc"] = master.expected_wkc

    wkcs = []

    def exchange(_k):
        master.send_processdata()
        wkcs.append(master.receive_processdata(5_000))

    every_ms(200, exchange)  # SYNC0 starts 100 ms after dc_sync
    master.state = pysoem.OP_STATE
    master.write_state()
    every_ms(20, exchange)
    report["op"] = master.state_check(pysoem.OP_STATE, 2_000_000)
    master.read_state()
    report["after_op"] = [s.state for s in slaves]

    def inputs():
        status, position, error = struct.unpack("<Hii", first.input[:10])
        return status, position, error

    def command(controlword, target):
        first.output = struct.pack("<Hi", controlword, target) + bytes(len(first.output) - 6)

    every_ms(5, exchange)
    start = inputs()[1]
    states = []
    for controlword, wanted in ((0x06, 0x21), (0x07, 0x23), (0x0F, 0x27)):
        command(controlword, start)

        def step(_k, controlword=controlword):
            exchange(_k)
            states.append(inputs()[0])

        every_ms(20, step)
        states_seen = inputs()[0] & 0x6F
        if states_seen != wanted:
            break
    report["statusword_enabled"] = inputs()[0]

    distance = round(10 * counts_per_mm)
    duration = 1000
    worst = {"following_error": 0, "fault": False}

    def move(k):
        t = min(1.0, k / duration)
        # A smooth start and stop: the cosine ramp of the distance.
        target = start + round(distance * (1 - math.cos(t * math.pi)) / 2)
        command(0x0F, target)
        exchange(k)
        status, _position, error = inputs()
        worst["following_error"] = max(worst["following_error"], abs(error))
        worst["fault"] = worst["fault"] or bool(status & 0x08) or bool(status & 0x2000)

    every_ms(duration + 200, move)
    report["start"] = start
    report["end"] = inputs()[1]
    report["distance"] = distance
    report["worst_following_error"] = worst["following_error"]
    report["fault"] = worst["fault"]
    report["window"] = FOLLOWING_ERROR_WINDOW
    report["wkc_low"] = sum(1 for w in wkcs if w < master.expected_wkc)
    report["frames"] = len(wkcs)
    report["dc_time"] = master.dc_time

    master.state = pysoem.INIT_STATE
    master.write_state()
    master.close()
    print(json.dumps(report))


if __name__ == "__main__":
    main()
