"""A command sent while a DRL Pause is still on its way (DXMC A.3, 0x6B05/0x6B06): the
Pause waits for the next line of main.lua, which a DELAY or a Till holds back. Driven by
pymodbus, a client luamotion did not write; the helpers are drl_client.py's.

The project writes DV 0x40 = 1..20 after its wait, one word every 50 ms, then ends;
its wait is DELAY(2) (project 7) or a Till on DV 0x41 in a module (project 8).

usage: drl_pending.py PORT delay-run | till-run | delay-stop
"""
import sys
import time

from drl_client import CONTROL, ID_SELECT, STATE, STATUS, connect, read, until, write

PROGRESS, RELEASE = 0x0040, 0x0041
CLOSE, RUNNING_STATE, PAUSE_STATE = 0, 1, 3
BUSY, RUNNING, STOPPED, CANNOT_RUN = 0, 21, 32, 20


def start_waiting(c, project):
    """Open & Release Run, then a Pause while the program waits: pending (BUSY)."""
    write(c, RELEASE, 0)
    write(c, PROGRESS, 0)
    write(c, ID_SELECT, project)
    write(c, CONTROL, 6)
    until("RUNNING", lambda: read(c, STATUS) == RUNNING)
    time.sleep(0.3)
    write(c, CONTROL, 4)  # Pause
    time.sleep(0.2)
    state, status = read(c, STATE), read(c, STATUS)
    assert (state, status) == (RUNNING_STATE, BUSY), f"a Pause during the wait is pending: state {state}, status {status}"
    assert read(c, PROGRESS) == 0, "the program is still waiting"
    print("pause pending during the wait")


def release_run(c, project):
    start_waiting(c, project)
    write(c, CONTROL, 2)  # Release Run
    status = read(c, STATUS)
    assert status in (BUSY, RUNNING), f"Release Run with a Pause pending: status {status}"
    if project == 8:
        write(c, RELEASE, 1)  # the Till's condition comes true
    seen = set()

    def ended():
        state = read(c, STATE)
        seen.add(state)
        return state == CLOSE

    until("the program to run on to its end", ended, timeout=15)
    assert PAUSE_STATE not in seen, f"the program paused: states seen {seen}"
    assert read(c, PROGRESS) == 20, f"DV 0x40 = {read(c, PROGRESS)}: the program did not run to its end"
    assert read(c, STATUS) == STOPPED, f"status {read(c, STATUS)} after the program's end"
    print("release run carried out: the program ran on to its end")


def stop(c, project):
    start_waiting(c, project)
    write(c, CONTROL, 3)  # Stop
    until("STOPPED and Close", lambda: read(c, STATUS) == STOPPED and read(c, STATE) == CLOSE)
    time.sleep(2.5)
    assert read(c, PROGRESS) == 0, "a stopped program wrote on"
    print("stop carried out: the program stopped in its wait")


def main():
    port, mode = int(sys.argv[1]), sys.argv[2]
    c = connect(port)
    {"delay-run": lambda: release_run(c, 7), "till-run": lambda: release_run(c, 8), "delay-stop": lambda: stop(c, 7)}[
        mode
    ]()
    print("ok")


if __name__ == "__main__":
    main()
