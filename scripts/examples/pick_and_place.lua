-- pick_and_place.lua: 30 s of a pick-and-place cycle on two axes, X = 2 * task and
-- Z = 2 * task + 1 (so task 0 uses axes 0 and 1): X to the pick station, Z down, close
-- the gripper (output 1 + task % 8), dwell, Z up, X to the place station, Z down, open,
-- dwell, Z up. It mostly waits: run it on the simulation clock with
--   luamotion run --clock sim --speed max scripts/examples/pick_and_place.lua
local x, z = 2 * _TASKID_, 2 * _TASKID_ + 1
local gripper = 1 + _TASKID_ % 8

local function move(axis, target)
  if MoveAbs(axis, target) ~= 0 then
    error(string.format("MoveAbs(%d, %g) failed: 0x%08x", axis, target, GetAxisLastErr(axis)))
  end
  Till(function() return IsInPos(axis) end)
end

for _, axis in ipairs({x, z}) do
  Enable(axis)
  Till(function() return IsEnabled(axis) end)
  SetVel(axis, 500)
  SetAcc(axis, 5000)
  SetDec(axis, 5000)
end

local picks = 0
while system_timeInMs < 30000 do
  move(x, 0)
  move(z, -50)
  SetGPO(gripper, 1)
  Sleep(100)
  move(z, 0)
  move(x, 300)
  move(z, -50)
  SetGPO(gripper, 0)
  Sleep(100)
  move(z, 0)
  picks = picks + 1
end

for _, axis in ipairs({x, z}) do
  Disable(axis)
end
Print("task %d: %d picks in %.1f s", _TASKID_, picks, system_timeInMs / 1000)
