"""A Modbus client luamotion did not write (pymodbus) loads a FUN147 step table into the
register image, starts the box by its EN relay and reads the status back (docs/fun147.md,
"Modbus").

usage: fun147_client.py PORT
"""
import sys

from drl_client import connect, read, until

R0, D0, M0 = 0x3000, 0x4B00, 0x5B20
SR, WR = R0 + 2000, D0 + 0


def d(n):
    return D0 + n


def relay_word(n):
    return M0 + n // 16, 1 << (n % 16)


def main():
    port = int(sys.argv[1])
    c = connect(port)
    # The table the Lua program assembled at R1000 (one step: SPD 4000, LIN ADR 1500,-700):
    # copied word for word to R2000, 10 words a request (DXMC 8.2).
    until("the table at R1000", lambda: read(c, R0 + 1000) == 0xA55C)
    table = read(c, R0 + 1000, 2) + read(c, R0 + 1002, 10) + read(c, R0 + 1012, 5)
    assert table[0] == 0xA55C and table[1] == 1, table
    for i in range(0, len(table), 10):
        r = c.write_registers(SR + i, table[i:i + 10], slave=1)
        assert not r.isError(), r
    # WR+0 = 0, then EN (M100) ON: bit 4 of the word of M96-M111.
    c.write_register(WR, 0, slave=1)
    word, bit = relay_word(100)
    c.write_register(word, read(c, word) | bit, slave=1)
    # DN (M112) and D4062 = 1, the positions DD4088/DD4090.
    until("DN", lambda: read(c, relay_word(112)[0]) & relay_word(112)[1])
    wr1 = read(c, WR + 1)
    pos = read(c, d(4088), 4)
    ps0 = pos[0] | pos[1] << 16
    ps1 = (pos[2] | pos[3] << 16) - (1 << 32 if pos[3] & 0x8000 else 0)
    print(f"WR+0 {read(c, WR)} DN {wr1 >> 14 & 1} D4062 {read(c, d(4062))} Ps0 {ps0} Ps1 {ps1}")
    # Addresses that do not exist: D4000 (0x5AA0) and past S999.
    for address in (0x5AA0, 0x5BDF):
        r = c.read_holding_registers(address, count=1, slave=1)
        assert r.isError(), f"0x{address:04X} answered {r}"
        print(f"0x{address:04X} exception {r.exception_code}")
    c.close()


if __name__ == "__main__":
    main()
