-- HMPL ch. 5 and 18 for the first API subset, checked from a script as a user
-- would. Each check names the manual section it covers.
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end

local a = 2

-- HMPL 5.2.1, table 18.1.2.1: a fresh axis is disabled; a move is refused with 0x83II0078.
check(IsEnabled(a) == false, "33: fresh axis not enabled (a Lua boolean)")
check(MoveAbs(a, 10) ~= 0, "33: MoveAbs on a disabled axis is refused")
check(GetAxisLastErr(a) == 0x83020078, string.format("33: last error 0x83020078, got 0x%08x", GetAxisLastErr(a)))
-- HMPL 18.1: axis codes carry 0x83 and the axis id.
check(GetAxisLastErr(a) >> 24 == 0x83 and (GetAxisLastErr(a) >> 16) & 0xFF == a, "91: 0x83IIEEEE layout")
check(GetAxisLastErr(a) & 0xFFFF == eERR_AXIS_CMD_INVALID_DISABLED, "error id constants")

-- HMPL 5.2.1: Enable returns 0 at once; the drive takes several cycles.
check(Enable(a) == 0, "34: Enable returns 0")
check(IsEnabled(a) == false, "34: not enabled in the cycle Enable was applied")
Till(function() return IsEnabled(a) end)

-- HMPL 5.3: non-positive profile values are refused with the matching code.
check(SetVel(a, 0) ~= 0 and GetAxisLastErr(a) == 0x83020140, "39: SetVel(0) -> 0x83II0140")
check(SetVel(a, -5) ~= 0, "39: SetVel(-5) refused")
check(SetAcc(a, 0) ~= 0 and GetAxisLastErr(a) == 0x8302014A, "39: SetAcc(0) -> 0x83II014A")
check(SetDec(a, -1) ~= 0 and GetAxisLastErr(a) == 0x83020154, "39: SetDec(-1) -> 0x83II0154")
check(SetVel(a, 200) == 0 and SetAcc(a, 2000) == 0 and SetDec(a, 2000) == 0, "39: positive values accepted")

-- HMPL 5.2.4: a move is under way at once, ends on its target, then settles in position.
check(MoveAbs(a, 100) == 0, "35: MoveAbs accepted")
check(IsMoving(a) == true and IsInPos(a) == false, "35: moving and not in position right after MoveAbs")
Till(function() return not IsMoving(a) end)
check(GetRefPos(a) == 100, "35: reference position exactly 100 when the profile ends")
Till(function() return IsInPos(a) end)
check(math.abs(GetPosFb(a) - 100) < 0.01, "35: feedback within the window")

-- HMPL 5.2.5: MoveRel from 100 by 10 ends at 110.
check(MoveRel(a, 10) == 0, "36: MoveRel accepted")
Till(function() return IsInPos(a) end)
check(GetRefPos(a) == 110, "36: MoveRel(10) from 100 -> 110")

-- Bad axis ids: commands return HMPL's "argument out of range"; queries raise an error.
check(MoveAbs(99, 1) == 0x138F, "commands on axis 99 return 0x0000138F")
local ok, err = pcall(IsEnabled, 99)
check(not ok and tostring(err):find("eERR_HMPL_ARG_OUT_OF_RANGE"), "queries on axis 99 raise 0x138F")
check(not pcall(MoveAbs, 0, "far"), "a string where a number belongs is a Lua error")

-- Constants of HMPL ch. 23.
check(PI == math.pi and TRUE == 1 and FALSE == 0, "23.1: PI, TRUE, FALSE")

Disable(a)
Till(function() return not IsEnabled(a) end)
check(MoveAbs(a, 0) ~= 0, "33: disabled again, moves refused")
Print("all checks passed")
