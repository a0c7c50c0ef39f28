-- hello_axis.lua: enable axis 0, move it 0 -> 100 -> 0 mm, print where it is.
local axis = 0

Enable(axis)
Till(function() return IsEnabled(axis) end)
Print("axis %d enabled at %.3f mm", axis, GetPosFb(axis))

for _, target in ipairs({100, 0}) do
  local rc = MoveAbs(axis, target)
  if rc ~= 0 then
    Print("MoveAbs failed: 0x%08x", GetAxisLastErr(axis))
    return
  end
  Till(function() return IsInPos(axis) end)
  Print("axis %d in position: ref %.3f mm, feedback %.3f mm", axis, GetRefPos(axis), GetPosFb(axis))
end

Disable(axis)
Till(function() return not IsEnabled(axis) end)
my_print("done")
