-- HMPL chapters 5.3 and 5.4: axis settings and status on the built-in machine.
local axis = 1

local function expect(rc, what)
  if rc ~= 0 then error(string.format("%s failed: 0x%08X", what, rc), 2) end
end
local function status()
  Print("enabled %s moving %s in-pos %s error-stop %s swrl %s", tostring(IsEnabled(axis)), tostring(IsMoving(axis)),
    tostring(IsInPos(axis)), tostring(IsErrorStop(axis)), tostring(IsSWRL(axis)))
end

Enable(axis) Till(function() return IsEnabled(axis) end)

-- Profile: velocity, acceleration by time (acc = vel / time), an S-curve by smooth time.
expect(SetVel(axis, 100), "SetVel")
expect(SetAccTime(axis, 50), "SetAccTime")
expect(SetDecTime(axis, 50), "SetDecTime")
expect(SetSMTime(axis, 20), "SetSMTime")
Print("vel %.0f acc %.0f dec %.0f smooth %.0f ms", GetVel(axis), GetAcc(axis), GetDec(axis), GetSMTime(axis))
-- Values out of range are refused and the last valid value stays.
if SetSMTime(axis, 600) == 0 then error("a smooth time of 600 ms must be refused") end

-- The in-position window: within 0.01 mm for 10 ms.
expect(SetPosWindow(axis, 0.01), "SetPosWindow")
expect(SetPosWindowTime(axis, 10), "SetPosWindowTime")

-- The velocity override (0..100 %) applies to the move under way.
MoveAbs(axis, 50)
Sleep(100)
expect(SetVelScale(axis, 50), "SetVelScale")
Sleep(300)
Print("at %.0f %% override: %.1f mm/s", GetVelScale(axis), GetRefVel(axis))
SetVelScale(axis, 100)
Till(function() return IsInPos(axis) end)

-- The axis variables: pos_out = ref_pos + compensation, pos_err = pos_out - pos_fb.
Print("ref %.4f out %.4f fb %.4f err %.4f", GetRefPos(axis), GetPosOut(axis), GetPosFb(axis), GetPosErr(axis))

-- SetPos redefines the present position by moving the origin.
expect(SetPos(axis, 0), "SetPos")
Print("after SetPos(0): fb %.3f, offset %.3f", GetPosFb(axis), GetPosOffset(axis))

-- A software right limit stops the axis in ErrorStop; Reset clears it; IgnoreSWL lets it pass.
expect(SetSWRL(axis, 20), "SetSWRL")
MoveAbs(axis, 30)
Till(function() return IsErrorStop(axis) and not IsMoving(axis) end)
status()
Print("stopped at %.3f mm, last error 0x%08X", GetRefPos(axis), GetAxisLastErr(axis))
expect(Reset(axis), "Reset")
expect(IgnoreSWL(axis, 1), "IgnoreSWL")
MoveAbs(axis, 30) Till(function() return IsInPos(axis) end)
IgnoreSWL(axis, 0)
SetSWRL(axis, 1000)
status()

-- Buffer mode 1 queues the moves; GetCmdNum counts those still waiting.
expect(SetBufferMode(axis, 1), "SetBufferMode")
MoveAbs(axis, 10) MoveAbs(axis, 20) MoveAbs(axis, 0)
Print("%d moves waiting", GetCmdNum(axis))
Till(function() return GetCmdNum(axis) == 0 and IsInPos(axis) end)
SetBufferMode(axis, 0)

-- Rollover: set while disabled; positions wrap at 360 and the turns are counted.
Disable(axis) Till(function() return not IsEnabled(axis) end)
expect(SetRollover(axis, 360), "SetRollover")
Enable(axis) Till(function() return IsEnabled(axis) end)
MoveRel(axis, 800) Till(function() return IsInPos(axis) end)
Print("rollover: %.3f after %d turns", GetPosFb(axis), GetRolloverTurns(axis))
Disable(axis) Till(function() return not IsEnabled(axis) end)
SetRollover(axis, 0)
Print("%d axes; chapter 5.3/5.4 done", GetAxisNum())
