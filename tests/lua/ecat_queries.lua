-- EtherCAT and slave information (HMPL 2.2-2.10, 17.2, 21) on the built-in machine.
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
check(GetECATSt() == 8 and IsSystemOper() and not IsSystemPreOp() and not IsSystemError(), "system in Op")
check(not IsSystemInit(), "initialised")
check(GetSlaveNum() == 4, "4 drives")
check(GetSlvECATSt(0) == 8 and GetSlvECATSt(3) == 8 and GetSlvECATSt(4) == -1, "slave states")
check(GetSlvChNum(0, 1) == 10 and GetSlvChNum(0, 2) == 5 and GetSlvChNum(0, 3) == 0, "channels of a D1")
check(GetSlvChNum(0, 5) == -1 and GetSlvChNum(0 | HMPL_SLOT_1, 1) == -1, "no such type or slot")
check(GetSlvSlotNum(0) == 0, "a drive has no slots")
check(ReadSDO(0, 0x1000, 0, 4) == 0x00020192, "device type")
check(ReadSDO(2, 0x1018, 2, 4) == 2, "product code of a D1")

-- Process data: the statusword is in the TxPDO, the controlword in the RxPDO.
local sw = ReadPDO(0, 0x6041, 0)
check(sw & 0x4F == 0x40 or sw & 0x6F == 0x21, string.format("statusword by PDO 0x%04x", sw))
check(ReadPDO(0, 0x6040, 0) == 0x0006, "the kernel holds a disabled drive in Shutdown")
check(ReadPDO(0, 0x6060, 0) == 8, "modes of operation mapped: csp")
check(ReadPDO(0, 0x60B1, 0) == -1, "0x60B1 is not mapped")
local rc, bytes = ReadPDOEx(0, 0x6041, 0)
check(rc == 0 and #bytes == 2 and bytes[1] == sw & 0xFF, "ReadPDOEx bytes")

-- A forced controlword wins over the kernel's, until released.
check(ForceWritePDO(0, 0x6040, 0, 0x000F) == 0, "force")
Till(function() return ReadPDO(0, 0x6041, 0) & 0x6F == 0x27 end)
check(ReleasePDO(0, 0x6040, 0) == 0 and ReleasePDO(0, 0x6040, 0) == -1, "release once")
Till(function() return ReadPDO(0, 0x6041, 0) & 0x6F == 0x21 end)
check(WritePDO(0, 0x6041, 0, 0) == -1, "the statusword is no output")

-- A drive fault reaches the axis: disabled, 0x83II03F2.
Enable(3)
Till(function() return IsEnabled(3) end)
check(SimDriveFault(3, 0x3110) == 0, "inject over voltage")
check(SimDriveFault(3, 0xFF03) == -1, "a D1 has no STO code")
Till(function() return not IsEnabled(3) end)
check(GetAxisLastErr(3) == 0x830303F2, string.format("drive fault 0x%08x", GetAxisLastErr(3)))
check(ReadSDO(3, 0x603F, 0, 2) == 0x3110, "0x603F")
Print("all checks passed")
