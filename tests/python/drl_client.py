"""A Modbus client luamotion did not write (pymodbus) drives a DRL project through the
DXMC registers (manual appendix A.3) and checks what an HMI would see.

usage: drl_client.py PORT scenario | dh-write VALUE | dh-read
"""
import sys
import time

from pymodbus.client import ModbusTcpClient

ID_SELECT, CONTROL, STATUS, STATE, LINE, SPEED, BP = 0x6B04, 0x6B05, 0x6B06, 0x6B01, 0x6B02, 0x6B03, 0x6B07
DV_VELOCITY, DH_WORD = 0x0010, 0x8000


def connect(port):
    client = ModbusTcpClient("127.0.0.1", port=port, timeout=5)
    assert client.connect(), "cannot connect"
    return client


def read(c, address, count=1):
    r = c.read_holding_registers(address, count=count, slave=1)
    assert not r.isError(), f"read 0x{address:04X}: {r}"
    return r.registers if count > 1 else r.registers[0]


def write(c, address, value):
    r = c.write_register(address, value, slave=1)
    assert not r.isError(), f"write 0x{address:04X}={value}: {r}"


def exception(r):
    assert r.isError(), f"expected an exception, got {r}"
    return r.exception_code


def until(what, f, timeout=10.0):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = f()
        if value:
            return value
        time.sleep(0.01)
    raise AssertionError(f"timed out waiting for {what}")


# BUSY, CHECKING, OPENING, STOPPING, EXPORTING, USB_ID_CHECKING, IMPORTING, BP_SETTING
IN_PROGRESS = {0, 1, 11, 31, 63, 66, 68, 71}


def control(c, code, expect):
    write(c, CONTROL, code)
    status = until(
        f"status {expect} after control {code}",
        lambda: (lambda s: None if s in IN_PROGRESS else s)(read(c, STATUS)),
    )
    assert status == expect, f"control {code}: status {status}, expected {expect}"


def peak_velocity(c, seconds):
    peak, end = 0, time.time() + seconds
    while time.time() < end:
        peak = max(peak, read(c, DV_VELOCITY))
        time.sleep(0.005)
    return peak


def scenario(port):
    c = connect(port)
    write(c, ID_SELECT, 5)
    control(c, 45, 21)  # Open & Debug Run -> RUNNING
    assert read(c, 0x6B00) == 5, "current DRL id"
    print("running: state", read(c, STATE))
    until("the line of main.lua while running", lambda: read(c, LINE) in range(4, 10))

    fast = peak_velocity(c, 1.5)
    write(c, SPEED, 50)
    time.sleep(0.5)
    slow = peak_velocity(c, 1.5)
    print(f"velocity at 100 %: {fast}, at 50 %: {slow}")
    assert 90 <= fast <= 106 and 0.45 <= slow / fast <= 0.55, (fast, slow)
    write(c, SPEED, 100)

    write(c, BP, 7)
    control(c, 42, 74)  # Add BP -> BP_ADDED
    until("break point", lambda: read(c, STATE) == 2)
    assert read(c, LINE) == 7, f"stopped at line {read(c, LINE)}"
    print("break point at line", read(c, LINE))
    control(c, 12, 51)  # Step Over -> STEPPED
    assert read(c, LINE) == 8, f"stepped to line {read(c, LINE)}"
    assert read(c, STATE) == 3, "after a step the program is paused"
    print("stepped to line", read(c, LINE))
    control(c, 43, 76)  # Delete BP
    control(c, 44, 21)  # Debug Run: on from the stop
    assert read(c, STATE) == 1
    control(c, 4, 41)  # Pause
    until("pause", lambda: read(c, STATE) == 3)
    control(c, 2, 21)  # Release Run
    control(c, 3, 32)  # Stop -> STOPPED
    assert read(c, STATE) == 0, "stopped: Close"

    # Bad requests: an exception each, and the server keeps serving.
    assert exception(c.read_holding_registers(0x0000, count=11, slave=1)) == 3, "11 words"
    assert exception(c.read_holding_registers(0x6000, count=1, slave=1)) == 2, "reserved address (SDV past the FUN147 image)"
    assert exception(c.write_register(STATUS, 1, slave=1)) == 2, "read-only register"
    assert exception(c.write_register(ID_SELECT, 10000, slave=1)) == 3, "DRL id 10000"
    assert exception(c.read_input_registers(0x0000, count=1, slave=1)) == 1, "FC 04"
    before = read(c, STATUS)
    write(c, CONTROL, 5)  # not a DRL command: alarm 0x7000, nothing else changes
    assert read(c, STATUS) == before
    c.close()
    c = connect(port)
    assert read(c, STATE) == 0, "a new client is served"
    print("bad requests refused; server still serving")


def controller_state(port):
    """DXMC 3.6 and A.3: 0x6A81 switches the state; motion only in Run or Diagnosis."""
    c = connect(port)
    assert read(c, 0x6A80) == 4, "the controller starts in Run"
    assert read(c, 0x6B11) == 7, "no machine-file task runs: PlcStop"
    write(c, ID_SELECT, 6)
    control(c, 6, 21)  # Open & Release Run
    write(c, 0x0030, 7)  # the project echoes DV 0x30 into DV 0x31 through ReadModbusWord
    until("echo", lambda: read(c, 0x0031) == 7)
    until("moves accepted in Run", lambda: read(c, 0x0021) == 0 and read(c, 0x0022) == 0)
    write(c, 0x6A81, 2)
    until("Edit", lambda: read(c, 0x6A80) == 2)
    until("moves refused in Edit", lambda: read(c, 0x0021) == 0x0020)
    assert read(c, 0x0022) == 0x1000, "alarm 0x1000_0020: motion core, axis 0, wrong mode"
    assert exception(c.write_register(0x6A81, 3, slave=1)) == 3, "3 is not a target state"
    write(c, 0x6A81, 5)
    until("Diagnosis", lambda: read(c, 0x6A80) == 5)
    until("moves accepted in Diagnosis", lambda: read(c, 0x0021) == 0)
    control(c, 3, 32)
    write(c, ID_SELECT, 6)
    control(c, 31, 65)  # Export -> EXPORT_DONE
    control(c, 32, 69)  # Import -> IMPORT_DONE
    write(c, ID_SELECT, 9)
    control(c, 31, 61)  # no project 9: FTP_ID_ERROR
    control(c, 32, 67)  # nothing exported as 9: USB_ID_ERROR
    print("controller state, export and import as the manual says")


def main():
    port, mode = int(sys.argv[1]), sys.argv[2]
    if mode == "scenario":
        scenario(port)
    elif mode == "controller-state":
        controller_state(port)
    elif mode == "dh-write":
        write(connect(port), DH_WORD, int(sys.argv[3]))
    elif mode == "dh-read":
        print("DH", read(connect(port), DH_WORD))
    print("ok")


if __name__ == "__main__":
    main()
