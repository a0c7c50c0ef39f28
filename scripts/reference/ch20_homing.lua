-- HMPL chapter 20 on the built-in machine (index pulse every 10 mm, home switch at
-- [-10, -5] mm). First example 20.1.1: the drive's homing, method 33 (index, negative).
local axis_id = 0
local home_method = HOME_METHOD_33
local fast_vel, slow_vel, acc, home_offsets, time_out = 20, 2, 2000, 0, 10000

Enable(axis_id) Till(function() return IsEnabled(axis_id) end)
MoveAbs(axis_id, 14) Till(function() return IsInPos(axis_id) end)

SetHomedStatus(axis_id, 0)
SetHomeMethod(axis_id, home_method)
SetHomeSwitchVel(axis_id, fast_vel)
SetHomeZeroVel(axis_id, slow_vel)
SetHomeAcc(axis_id, acc)
SetHomeOffset(axis_id, home_offsets)
SetHomeTimeout(axis_id, time_out)
local result = MoveHome(axis_id)                  -- returns when the homing is over
if not IsHoming(axis_id) and result == 0 then
  SetHomedStatus(axis_id, 1)
  Print("Home success at %.3f mm.", GetPosFb(axis_id))
else
  SetHomedStatus(axis_id, 0)
  Print("Home fail: 0x%08X.", result)
end

-- A user-defined homing on the home switch: jog towards it, latch where it turns on,
-- stop, and make that edge the origin.
MoveAbs(axis_id, 20) Till(function() return IsInPos(axis_id) end)
SetHomedStatus(axis_id, 0)
local edge
MoveVel(axis_id, -10)
Till(function()
  if IsHomeSwitch(axis_id) then edge = GetPosFb(axis_id) end
  return edge ~= nil or not IsMoving(axis_id) or IsHWLL(axis_id)
end)
Stop(axis_id) Till(function() return not IsMoving(axis_id) end)
if edge and IsEnabled(axis_id) then
  SetPos(axis_id, GetPosFb(axis_id) - edge)
  MoveAbs(axis_id, 0) Till(function() return IsInPos(axis_id) end)
  SetHomedStatus(axis_id, 1)
  Print("switch edge is the origin; homed %s", tostring(IsHomed(axis_id)))
else
  SetHomedStatus(axis_id, 0)
  Print("Axis homing fails.")
end
Print("chapter 20 done")
