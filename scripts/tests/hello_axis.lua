-- A test program for `luamotion test scripts/tests`: a fresh controller on the built-in
-- machine runs it; every expect_* that fails is reported with its line, and the file fails.
local axis = 0

Enable(axis)
Till(function() return IsEnabled(axis) end)
expect_near(GetPosFb(axis), 0, 1e-3, "starts at 0")

for _, target in ipairs({100, -25, 0}) do
  expect_eq(MoveAbs(axis, target), 0, "MoveAbs accepted")
  expect_true(IsMoving(axis), "moving right after MoveAbs")
  Till(function() return IsInPos(axis) end)
  expect_near(GetPosFb(axis), target, 1e-3, "in position")
end

-- A refused command returns the manual's code: velocity beyond 0..100 % (HMPL 5.3.37).
expect_eq(SetVelScale(axis, 120) & 0xFFFF, 0x017C)

Disable(axis)
Till(function() return not IsEnabled(axis) end)
expect_true(not IsEnabled(axis))
