"""A Modbus TCP server luamotion did not write (pymodbus) for the HMPL 22.3 client tests:
every table from address 0, with values the tests know, at unit id 1 only: requests for
another unit get no answer, as from a gateway with one RTU device behind it.

usage: modbus_server.py PORT
  holding registers: 0 (written by the tests)   input registers: 1000 + address
  coils: off (written by the tests)             discrete inputs: on where address % 3 == 0
"""
import asyncio
import sys

from pymodbus.datastore import ModbusSequentialDataBlock, ModbusServerContext, ModbusSlaveContext
from pymodbus.server import StartAsyncTcpServer

SIZE = 4000


def block(values):
    # Without zero_mode pymodbus adds 1 to every request address: a block from 1 is from 0.
    return ModbusSequentialDataBlock(1, values)


async def main(port):
    store = ModbusSlaveContext(
        di=block([a % 3 == 0 for a in range(SIZE)]),
        co=block([False] * SIZE),
        hr=block([0] * SIZE),
        ir=block([(1000 + a) & 0xFFFF for a in range(SIZE)]),
    )
    await StartAsyncTcpServer(
        context=ModbusServerContext(slaves={1: store}, single=False),
        address=("127.0.0.1", port),
        ignore_missing_slaves=True,
    )


if __name__ == "__main__":
    asyncio.run(main(int(sys.argv[1])))
