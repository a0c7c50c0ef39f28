-- HMPL 8.2.13 to 8.2.17: the arcs and circles of the manual's own examples, each from the
-- point the manual starts it at.
local gid = 0
Enable(0); Enable(1)
Till(function() return IsEnabled(0) and IsEnabled(1) end)
SetupGroup(gid, 0, 1)
SetGrpMotionProfile(gid, 200, 5000, 5000, 20)

local function go(x, y)
  LineAbs2D(gid, x, y)
  Till(function() return IsGrpInPos(gid) end)
end

local function at(what)
  Till(function() return IsGrpInPos(gid) end)
  local _, p = GetGrpPoseCmd(gid, CS_MCS)
  Print("%-32s ends at (%.3f, %.3f)", what, p[1], p[2])
end

go(0, 0)
Arc2D(gid, 100, 100, 200, 0)          -- 8.2.13: through (100, 100)
at("Arc2D via (100,100) to (200,0)")
go(0, 0)
ArcAngle2D(gid, 10, 10, 45)           -- 8.2.16: to (10, 10 - 10*sqrt(2))
at("ArcAngle2D about (10,10) by 45")
go(0, 0)
Circle2D(gid, 100, 0, 200, 0, 1)      -- 8.2.17: half a circle, counter-clockwise
at("Circle2D (100,0) to (200,0), 1")
go(0, 0)
ArcCW2D(gid, 50, 0, 100, 0)           -- 8.2.14
at("ArcCW2D about (50,0) to (100,0)")
ArcCCW2D(gid, 50, 0, 0, 0)            -- 8.2.15: back the other way round
at("ArcCCW2D about (50,0) to (0,0)")
-- Start and end radii that differ are refused (0x82II0280), nothing moves.
Print("ArcCW2D with radii 10 and 30: 0x%08X", ArcCW2D(gid, 10, 0, 30, 0))
Print("last group error 0x%08X; chapter 8 arcs done", GetGrpLastErr(gid))
