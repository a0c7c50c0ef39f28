-- serial_selftest.lua: the DXMC manual's serial FreePort self-test (8.3, "Lua 脚本撰写"),
-- as printed. On the DXMC, 485+ and 485- are shorted; here the machine file says
-- `[serial] loopback = true` (scripts/examples/serial_loopback.toml):
--   luamotion run --config scripts/examples/serial_loopback.toml scripts/examples/serial_selftest.lua
-- prints `>Rx: Rtn:0x0 Data:3.1415`.
--1.===设定开始/终止符，并清除接收缓冲区 ...
P309,Err1,Err2 = FreePort.Serial.Init(1,":",";")
--2.===自发自收测试 ...
FreePort.Serial.Tx(1,"3.1415")
DELAY(0.1)
local RxValid, RxData = FreePort.Serial.Rx(1)
my_print(string.format (">Rx: Rtn:0x%x Data:%s", RxValid,RxData))
--可收到 3.1415 字符串
