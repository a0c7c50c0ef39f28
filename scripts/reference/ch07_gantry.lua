-- HMPL chapter 7, example 7.1.1: axes 0 (right-hand) and 1 (left-hand) as a gantry.
-- Commands to axis 0 move the linear axis, commands to axis 1 the yaw.
local axis_0, axis_1 = 0, 1

DisableGantryPair(axis_0)                           -- remove an existing pair
Till(function() return not IsGantry(axis_0) and not IsGantry(axis_1) end)
Disable(axis_0) Till(function() return not IsEnabled(axis_0) end)
Disable(axis_1) Till(function() return not IsEnabled(axis_1) end)

local rc = EnableGantryPair(axis_0, axis_1)         -- both must be disabled
if rc ~= 0 then error(string.format("EnableGantryPair: 0x%08X", rc)) end
Enable(axis_0)                                      -- enabling one enables the pair
Till(function() return IsEnabled(axis_0) and IsEnabled(axis_1) end)
Till(function() return IsGantry(axis_0) and IsGantry(axis_1) end)
Print("gantry pair %d", GetGantryPairID(axis_0))

MoveAbs(axis_0, 50) Till(function() return IsInPos(axis_0) end)   -- linear 50 mm
MoveAbs(axis_1, 2) Till(function() return IsInPos(axis_1) end)    -- yaw 2 mm
-- Linear = (R + L) / 2, yaw = (R - L) / 2; the drives themselves sit at R and L.
local r, l = ReadPDO(axis_0, 0x6064, 0) / 10000, ReadPDO(axis_1, 0x6064, 0) / 10000
Print("drives R %.3f L %.3f -> linear %.3f yaw %.3f", r, l, GetPosFb(axis_0), GetPosFb(axis_1))

MoveAbs(axis_1, 0) Till(function() return IsInPos(axis_1) end)
MoveAbs(axis_0, 0) Till(function() return IsInPos(axis_0) end)
Disable(axis_0) Till(function() return not IsEnabled(axis_0) and not IsEnabled(axis_1) end)
DisableGantryPair(axis_0)                           -- split only while disabled
Print("chapter 7 done")
