-- HMPL chapter 5.2: axis motion control on the built-in machine (4 axes, mm, 1 ms).
-- Every motion function returns 0 or the error code it also stores for GetAxisLastErr.
local axis = 0

local function expect(rc, what)
  if rc ~= 0 then error(string.format("%s failed: 0x%08X", what, rc), 2) end
end

-- 5.2.1 Enable is non-blocking: wait for the drive to reach Operation enabled.
expect(Enable(axis), "Enable")
Till(function() return IsEnabled(axis) end)

-- 5.2.4 / 5.2.5: absolute and relative moves with the axis' profile (SetVel/SetAcc/SetDec).
SetVel(axis, 200) SetAcc(axis, 2000) SetDec(axis, 2000)
expect(MoveAbs(axis, 100), "MoveAbs")
Till(function() return IsInPos(axis) end)
expect(MoveRel(axis, -30), "MoveRel")
Till(function() return IsInPos(axis) end)
Print("at %.3f mm (move %.0f ms, settling %.0f ms)", GetPosFb(axis), GetMoveTime(axis), GetSettlingTime(axis))

-- 5.2.6 / 5.2.9: jog at -50 mm/s for half a second, then Stop (decelerates, clears the plan).
expect(MoveVel(axis, -50), "MoveVel")
Sleep(500)
Print("jogging at %.1f mm/s", GetRefVel(axis))
expect(Stop(axis), "Stop")
Till(function() return not IsMoving(axis) end)

-- 5.2.10 / 5.2.11: Halt pauses a move, Resume carries on to the same target.
expect(MoveAbs(axis, 150), "MoveAbs")
Sleep(300)
expect(Halt(axis), "Halt")
Till(function() return not IsMoving(axis) end)
Print("halted at %.3f mm", GetRefPos(axis))
expect(Resume(axis), "Resume")
Till(function() return IsInPos(axis) end)
Print("resumed to %.3f mm", GetRefPos(axis))

-- 5.2.8: MovePVT, the manual's example (times ms from 0, positions mm, velocities mm/s),
-- starting where the axis stands: first bring it to the first point.
MoveAbs(axis, 0) Till(function() return IsInPos(axis) end)
local point    = {0.0, 153.333, 42.123, 161.21, 177.0, 83.333}
local velocity = {0.0, 1000.0, 800.0, 1660.0, 450.0, 0.0}
local time     = {0.0, 2000.0, 3000.0, 4000.0, 6000.0, 11000.0}
expect(MovePVT(axis, time, point, velocity, 6), "MovePVT")
Till(function() return not IsMoving(axis) end)
Print("PVT ended at %.3f mm", GetRefPos(axis))

-- 5.2.7: MoveTrq needs the cyclic synchronous torque mode (SetOpMode 10).
expect(SetOpMode(axis, 10), "SetOpMode(cst)")
expect(MoveTrq(axis, 0.2), "MoveTrq")
Sleep(100)
Print("torque mode: current %.3f A", GetCurrFb(axis))
MoveTrq(axis, 0)
expect(SetOpMode(axis, 8), "SetOpMode(csp)")

-- 5.2.2: Disable clears the path planning.
expect(Disable(axis), "Disable")
Till(function() return not IsEnabled(axis) end)
Print("chapter 5.2 done")
