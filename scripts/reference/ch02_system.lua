-- HMPL chapter 2: system functions. Out-parameters come back after the return code.
Print("system: init %s, oper %s, pre-op %s, error %s", tostring(IsSystemInit()), tostring(IsSystemOper()),
  tostring(IsSystemPreOp()), tostring(IsSystemError()))
Print("EtherCAT state %d, slave 0 state %d, %d slaves", GetECATSt(), GetSlvECATSt(0), GetSlaveNum())

-- 2.11 to 2.15: what the controller is.
local rc, ver_buf = GetFirmwareVer()
Print("%s", ver_buf) -- the firmware version: luamotion's own
local _, date = GetFirmwareDate()
local _, hash = GetFirmwareHash()
local _, model = GetModelNum()
local _, sn = GetSerialNum()
Print("firmware %s of %s, hash %016X", ver_buf, date, hash)
Print("model %s, serial %s", model, sn)

-- 2.16 ScanNetwork: not while an axis is enabled.
local axis = 0
Print("ScanNetwork with every axis disabled: %d", ScanNetwork())
Enable(axis) Till(function() return IsEnabled(axis) end)
Print("ScanNetwork with axis %d enabled: 0x%04X, last system error 0x%04X", axis, ScanNetwork(), GetSystemLastErr())
Disable(axis) Till(function() return not IsEnabled(axis) end)
Print("after a rescan: %d, EtherCAT state %d", ScanNetwork(), GetECATSt())
-- The axes run on the rescanned network as before.
Enable(axis) Till(function() return IsEnabled(axis) end)
local from = GetPosFb(axis)
MoveRel(axis, 10) Till(function() return IsInPos(axis) end)
Print("moved %.3f mm after the rescan", GetPosFb(axis) - from)

-- 2.17 SetHMIScope: start and stop recording (the event stream hears of it).
Print("SetHMIScope(1) %d, SetHMIScope(0) %d, SetHMIScope(2) 0x%04X", SetHMIScope(1), SetHMIScope(0), SetHMIScope(2))

-- 2.18 Sleep, 2.24 TON: the output rises PT ms after the input.
local timer = TimerInit()
local start = system_timeInMs
local q = TON(timer, true, 100)
Till(function() return TON(timer, true, 100) end)
Print("TON: %s at first, true after %d ms", tostring(q), system_timeInMs - start >= 100 and 100 or -1)

-- 2.22, 2.23 mutexes.
MutexLock(0) MutexUnlock(0)
Print("chapter 2 done")
