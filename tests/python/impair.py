"""A cable that loses, delays or duplicates EtherCAT frames, for a kernel without netem:
forwards every EtherType 0x88A4 frame between two interfaces in both directions; from
SIGUSR1 on it drops a share of them, holds each for a delay, or sends a share twice (as
`tc netem` on a running link would). Runs until killed.

usage: impair.py IF_A IF_B LOSS DELAY_US DUPLICATE   (LOSS and DUPLICATE as fractions)
"""

import heapq
import os
import random
import select
import signal
import socket
import sys
import time

ETH_P_ECAT = 0x88A4
PACKET_OUTGOING = 4


def open_raw(interface):
    s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETH_P_ECAT))
    s.bind((interface, ETH_P_ECAT))
    s.setblocking(False)
    return s


def main():
    # A cable does not wait for a CPU: as root the forwarder runs at SCHED_FIFO, below the
    # segment (70) and the controller (80).
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(60))
    except PermissionError:
        print("SCHED_FIFO refused; the forwarder runs as a plain process", file=sys.stderr)
    a, b = open_raw(sys.argv[1]), open_raw(sys.argv[2])
    impairment = (float(sys.argv[3]), float(sys.argv[4]) * 1e-6, float(sys.argv[5]))
    loss, delay, duplicate = 0.0, 0.0, 0.0

    def impair(_signal, _frame):
        nonlocal loss, delay, duplicate
        loss, delay, duplicate = impairment

    signal.signal(signal.SIGUSR1, impair)
    other = {a: b, b: a}
    queue = []  # (due, sequence, socket, frame)
    sequence = 0
    rng = random.Random(39)
    print("forwarding", flush=True)
    while True:
        timeout = max(0.0, queue[0][0] - time.monotonic()) if queue else 0.1
        try:
            ready, _, _ = select.select([a, b], [], [], timeout)
        except InterruptedError:
            continue
        now = time.monotonic()
        for s in ready:
            while True:
                try:
                    frame, address = s.recvfrom(2048)
                except BlockingIOError:
                    break
                if address[2] == PACKET_OUTGOING or rng.random() < loss:
                    continue
                copies = 2 if rng.random() < duplicate else 1
                for _ in range(copies):
                    sequence += 1
                    heapq.heappush(queue, (now + delay, sequence, other[s], frame))
        while queue and queue[0][0] <= time.monotonic():
            _, _, s, frame = heapq.heappop(queue)
            try:
                s.send(frame)
            except OSError:
                pass


main()
