-- HMPL chapter 8, example 8.1.6-1 on the built-in machine: axes 0 and 1 as X and Y of
-- group 0, a line there and back, then the relative line of 8.2.11.
local gid = 0
UngrpAllAxes(gid)                                   -- optional: clear the group, disable it
Enable(0); Enable(1)
Till(function() return IsEnabled(0) and IsEnabled(1) end)
SetGrpMotionProfile(gid, 100, 5000, 5000, 200)      -- vel, acc, dec, smooth time (ms) of the TCP
SetupGroup(gid, 0, 1)                               -- AddAxisToGrp(gid, 0); AddAxisToGrp(gid, 1); EnableGroup(gid)
Print("group of axis 0: %d, of axis 2: %d; enabled %s", GetGroupID(0), GetGroupID(2), tostring(IsGrpEnabled(gid)))
Print("vel %.0f acc %.0f dec %.0f smooth %.0f ms", GetGrpVel(gid), GetGrpAcc(gid), GetGrpDec(gid), GetGrpSMTime(gid))

LineAbs2D(gid, 100, 100)
Print("moving %s", tostring(IsGrpMoving(gid)))
Till(function() return IsGrpInPos(gid) end)
Print("at (%.3f, %.3f)", GetPosFb(0), GetPosFb(1))
LineAbs2D(gid, 0.0, 0.0)
Till(function() return IsGrpInPos(gid) end)

-- 8.2.11: from (100, 200) by (100, 100) to (200, 300).
LineAbs2D(gid, 100, 200)
LineRel2D(gid, 100, 100)
Print("%d commands queued", GetGrpCmdNum(gid))
Till(function() return IsGrpInPos(gid) end)
local rc, pose = GetGrpPoseCmd(gid, CS_MCS)
Print("LineRel2D ends at (%.3f, %.3f)", pose[1], pose[2])

-- An axis of a group moves only with it (0x83II00E6).
Print("MoveAbs on a grouped axis: 0x%08X", MoveAbs(0, 5))
UngrpAllAxes(gid)
Print("after UngrpAllAxes: group of axis 0 %d; chapter 8 lines done", GetGroupID(0))
