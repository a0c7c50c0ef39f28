-- HMPL 8.1.6 examples 2 and 3-2: per-command profiles with buffer modes, then the
-- rectangle with its corners rounded by TM_CORNER_DIST.
local axis = {0, 1}
local gid = 0
UngrpAllAxes(gid)
Enable(axis[1]); Enable(axis[2])
Till(function() return IsEnabled(axis[1]) and IsEnabled(axis[2]) end)
AddAxisToGrp(gid, axis[1]); AddAxisToGrp(gid, axis[2]); EnableGroup(gid)

local c1 = {100, 50, 0}
local c2 = {0, 50, 0}
local p0 = {0, 0, 0, 0, 0, 0}
local p1 = {100, 0, 0, 0, 0, 0}
local p2 = {100, 100, 0, 0, 0, 0}
local p3 = {0, 100, 0, 0, 0, 0}
local norm_ccw = {0, 0, 1}
local vel_high = {150, 1000, 1000, 50}
local vel = {100, 5000, 5000, 50}
local vel_low = {50, 250, 250, 50}
local trans_para = {0, 0, 0, 0}

LineAbs(gid, p0, vel, CS_MCS, BM_BUFF, TM_NONE, trans_para); Till(function() return IsGrpInPos(gid) end)
LineAbs(gid, p1, vel_high, CS_MCS, BM_PREV, TM_NONE, trans_para)                 -- path 1
CircleAbs(gid, c1, norm_ccw, 0, p2, vel, CS_MCS, BM_NEXT, TM_NONE, trans_para)   -- path 2
LineAbs(gid, p3, vel_low, CS_MCS, BM_PREV, TM_NONE, trans_para)                  -- path 3
Print("3 paths queued: %d commands", GetGrpCmdNum(gid))
Till(function() return IsGrpInPos(gid) end)
CircleAbs(gid, c2, norm_ccw, 0, p0, vel, CS_MCS, BM_BUFF, TM_NONE, 0)           -- path 4, NULL trans_par
Till(function() return IsGrpInPos(gid) end)
local _, p = GetGrpPoseCmd(gid, CS_MCS)
Print("example 2 back at (%.3f, %.3f)", p[1], p[2])

-- Example 3-2: the rectangle, sharp and then with its corners rounded 20 mm either side.
local function rectangle()
  LineAbs2D(gid, 0, 0); LineAbs2D(gid, 100, 0); LineAbs2D(gid, 100, 100)
  LineAbs2D(gid, 0, 100); LineAbs2D(gid, 0, 0)
end
rectangle(); Till(function() return IsGrpInPos(gid) end)
SetGrpBufferMode(gid, BM_LOW)
SetGrpTransMode(gid, TM_CORNER_DIST)
SetGrpTransPrm(gid, 50, 20, 0, 0)
rectangle()
LineAbs2D(gid, 0 + 20, 0)
Print("rounded rectangle queued as %d segments", GetGrpCmdNum(gid))
Till(function() return IsGrpInPos(gid) end)
_, p = GetGrpPoseCmd(gid, CS_MCS)
Print("example 3-2 ends at (%.3f, %.3f), transition mode %d", p[1], p[2], GetGrpTransMode(gid))
SetGrpTransMode(gid, TM_NONE)
Print("chapter 8 blending done")
