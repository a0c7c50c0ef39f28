-- A contour on axes 0 (X) and 1 (Y): a plate with a rounded end, a chamfer and a
-- rounded corner, drawn as one blended path. Run it with a trace to see the axes move together:
--   luamotion run --trace contour.csv scripts/examples/contour.lua
local gid = 0
UngrpAllAxes(gid)
Enable(0); Enable(1)
Till(function() return IsEnabled(0) and IsEnabled(1) end)
SetupGroup(gid, 0, 1)

-- The path speed, its acceleration and the S-curve's smooth time.
SetGrpMotionProfile(gid, 200, 4000, 4000, 20)
-- Move to the start at rest, then plan the contour with look-ahead: the controller slows
-- down only where the corners and arcs need it.
LineAbs2D(gid, 0, 0)
Till(function() return IsGrpInPos(gid) end)
SetGrpBufferMode(gid, BM_LOOKAHEAD)
SetGrpLookAheadPrm(gid, 0, 2000)     -- corner acceleration, mm/s²
SetGrpLookAheadPrm(gid, 1, 1000)     -- arc acceleration, mm/s²
-- Round every sharp corner: leave each line 5 mm before the corner, join the next 5 mm after.
SetGrpTransMode(gid, TM_CORNER_DIST)
SetGrpTransPrm(gid, 100, 5, 0, 0)

LineAbs2D(gid, 150, 0)               -- bottom edge
ArcCCW2D(gid, 150, 40, 150, 80)      -- right end: a half circle of radius 40
LineAbs2D(gid, 60, 80)               -- top edge
LineAbs2D(gid, 40, 60)               -- a chamfer
LineAbs2D(gid, 40, 40)
ArcCW2D(gid, 0, 40, 0, 0)            -- a quarter circle back to the start
Print("contour queued: %d segments", GetGrpCmdNum(gid))

local fastest = 0
Till(function()
  local vx, vy = GetVelFb(0), GetVelFb(1)
  fastest = math.max(fastest, math.sqrt(vx * vx + vy * vy))
  return IsGrpInPos(gid)
end)
local _, p = GetGrpPoseCmd(gid, CS_MCS)
Print("contour done at (%.3f, %.3f); fastest %.0f mm/s", p[1], p[2], fastest)
SetGrpTransMode(gid, TM_NONE)
SetGrpBufferMode(gid, BM_BUFF)
