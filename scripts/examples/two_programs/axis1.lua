-- Moves axis 1 while axis0.lua moves axis 0, each in its own process.
local axis = 1
Enable(axis)
Till(function() return IsEnabled(axis) end)
SetVel(axis, 200)
MoveRel(axis, -80)
Till(function() return IsInPos(axis) end)
Print("axis %d at %.3f mm", axis, GetPosFb(axis))
MoveAbs(axis, 0)
Till(function() return IsInPos(axis) end)
Print("axis %d back at %.3f mm", axis, GetPosFb(axis))
Disable(axis)
