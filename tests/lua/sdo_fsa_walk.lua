-- An integrator brings drive 1 to Operation enabled by SDO alone, as on a real drive:
-- write the controlword 0x6040, read the statusword 0x6041 (CoE manual 3.1, tables
-- 3-3 and 3-5). The machine file leaves 0x6040 out of slave 1's RxPDO, so the motion
-- kernel does not write it every cycle.
local slave = 1
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
local function state()
  local sw = ReadSDO(slave, 0x6041, 0, 2)
  check(sw >= 0, "statusword readable")
  if sw & 0x4F == 0x40 then return "switch on disabled" end
  if sw & 0x6F == 0x21 then return "ready to switch on" end
  if sw & 0x6F == 0x23 then return "switched on" end
  if sw & 0x6F == 0x27 then return "operation enabled" end
  if sw & 0x6F == 0x07 then return "quick stop active" end
  if sw & 0x4F == 0x08 then return "fault" end
  return string.format("0x%04x", sw)
end
local function command(cw, expected)
  check(WriteSDO(slave, 0x6040, 0, 2, cw) == 0, string.format("write controlword 0x%04x", cw))
  Till(function() return state() == expected end)
  Print("0x%04X -> %s", cw, expected)
end

check(state() == "switch on disabled", "power-up state")
check(Enable(slave) ~= 0, "the kernel cannot enable an axis whose controlword is not mapped")
check(GetAxisLastErr(slave) == 0x83010258, "0x83II0258: PDO lacks a required object")
command(0x0006, "ready to switch on")
command(0x0007, "switched on")
command(0x000F, "operation enabled")
command(0x000B, "quick stop active")
command(0x0000, "switch on disabled")
command(0x000F, "switch on disabled")   -- Enable operation needs Shutdown first (CoE 3.1)
command(0x0006, "ready to switch on")
command(0x000F, "operation enabled")    -- 0x000F goes through (transitions 3+4)
check(WriteSDO(slave, 0x6041, 0, 2, 0) == -1, "the statusword is read-only")
check(ReadSDO(slave, 0x6041, 0, 4) == -1, "a length that is not the object's fails")
local rc, bytes = ReadSDOEx(slave, 0x1018, 1, 4)
check(rc == 0 and bytes[1] == 0xAA and bytes[2] == 0xAA and bytes[3] == 0 and #bytes == 4, "vendor id bytes")
check(WriteSDOEx(slave, 0x6040, 0, 2, {0x06, 0x00}) == 0, "WriteSDOEx from a byte table")
Till(function() return state() == "ready to switch on" end)
Print("done")
