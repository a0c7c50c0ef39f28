-- HMPL 8.1.6 example 4: full circles in the XY, XZ and YZ planes chosen by their normal
-- vectors, then a helix of five turns while Z rises to 100.
local axis = {0, 1, 2}
local gid = 0
local center1 = {0, 50, 0}
local center2 = {0, 0, 50}
local end_pos = {0, 0, 0, 0, 0, 0}
local norm_x = {1, 0, 0}
local norm_y = {0, 1, 0}
local norm_z = {0, 0, 1}
local vel = {100, 5000, 5000, 50}

UngrpAllAxes(gid)
Enable(axis[1]); Enable(axis[2]); Enable(axis[3])
Till(function() return IsEnabled(axis[1]) and IsEnabled(axis[2]) and IsEnabled(axis[3]) end)
SetupGroup(gid, axis[1], axis[2], axis[3])
SetGrpMotionProfile(gid, 500, 20000, 20000, 10)
local fast = {500, 20000, 20000, 10}
LineAbs3D(gid, 0, 0, 0)
CircleAbs(gid, center1, norm_z, 1, end_pos, fast, CS_MCS, BM_BUFF, TM_NONE, 0)   -- full circle in XY
CircleAbs(gid, center2, norm_y, 1, end_pos, fast, CS_MCS, BM_BUFF, TM_NONE, 0)   -- full circle in XZ
CircleAbs(gid, center2, norm_x, 1, end_pos, fast, CS_MCS, BM_BUFF, TM_NONE, 0)   -- full circle in YZ
local highest_y, highest_z = 0, 0
Till(function()
  local _, p = GetGrpPoseCmd(gid, CS_MCS)
  highest_y = math.max(highest_y, p[2]); highest_z = math.max(highest_z, p[3])
  return IsGrpInPos(gid)
end)
Print("three circles: Y reached %.1f, Z reached %.1f, back at (%.3f, %.3f, %.3f)",
  highest_y, highest_z, GetPosFb(0), GetPosFb(1), GetPosFb(2))
end_pos[3] = 100
CircleAbs(gid, center1, norm_z, 5, end_pos, fast, CS_MCS, BM_BUFF, TM_NONE, 0)   -- helix, Z 0 -> 100
Till(function() return IsGrpInPos(gid) end)
local _, p = GetGrpPoseCmd(gid, CS_MCS)
Print("helix ends at (%.3f, %.3f, %.3f)", p[1], p[2], p[3])
LineAbs3D(gid, 0, 0, 0)
Till(function() return IsGrpInPos(gid) end)
Print("chapter 8 helix done")
