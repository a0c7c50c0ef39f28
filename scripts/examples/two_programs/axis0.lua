-- Moves axis 0 back and forth while axis1.lua moves axis 1, each in its own process.
local axis = 0
Enable(axis)
Till(function() return IsEnabled(axis) end)
for cycle = 1, 2 do
  MoveAbs(axis, 50)
  Till(function() return IsInPos(axis) end)
  MoveAbs(axis, 0)
  Till(function() return IsInPos(axis) end)
  Print("axis %d: round trip %d done at %.3f mm", axis, cycle, GetPosFb(axis))
end
Disable(axis)
