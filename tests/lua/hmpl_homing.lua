-- HMPL ch. 20 (homing), on the built-in machine: index every
-- 10 mm at 0, 10, 20 ... mm; home switch [-10, -5] mm.
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
local a = 0
Enable(a) Till(function() return IsEnabled(a) end)

-- HMPL 20.1, 20.9: defaults and the homed flag.
check(not IsHomed(a), "93: not homed at first")
check(SetHomedStatus(a, 1) == 0 and IsHomed(a), "93: SetHomedStatus")
SetHomedStatus(a, 0)

-- HMPL 20.3: unsupported methods are refused; 37 makes here the home, no motion.
check(SetHomeMethod(a, 3) ~= 0 and GetAxisLastErr(a) == 0x8300012C, "94: method 3 refused")
MoveAbs(a, 12.5) Till(function() return IsInPos(a) end)
SetHomeMethod(a, HOME_METHOD_37)
SetHomeOffset(a, 100)
check(MoveHome(a) == 0 and IsHomed(a) and not IsHoming(a), "94: 37 homes")
check(math.abs(GetPosFb(a) - 100) < 0.01, "94: here reads the offset, 100")

-- HMPL 20.1, 20.8: method 33 ends on the first index in the negative direction.
MoveAbs(a, 115) Till(function() return IsInPos(a) end)   -- 15 mm of the machine
SetHomeMethod(a, 33)
SetHomeOffset(a, 0)
check(MoveHome(a) == 0 and IsHomed(a), "95: method 33")
Sleep(20)
check(math.abs(GetPosFb(a)) < 0.01, "95: position = home offset 0")
MoveAbs(a, 3) Till(function() return IsInPos(a) end)
check(math.abs(ReadPDO(a, 0x6064, 0) / 10000 - 3) < 0.01, "at the index (10 mm of the machine) + 3")

-- HMPL 20.1, 20.8: a timeout shorter than the homing.
SetHomeMethod(a, 1)            -- far away: the negative limit at -1000 mm
SetHomeTimeout(a, 100)
check(MoveHome(a) == 0x83000424 and not IsHomed(a), "95: timeout 0x83II0424")
check(IsHomeSwitch(a) == false, "20.12: not on the home switch")

-- A method the drive does not have fails in the drive (HMPL allows 17, the HIWIN drive not).
SetHomeTimeout(a, 120000)
SetHomeMethod(a, 17)
check(MoveHome(a) == 0x8300042E, "a homing the drive refuses: 0x83II042E")
Print("homing facts passed")
