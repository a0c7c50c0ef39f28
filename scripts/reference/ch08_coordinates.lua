-- HMPL 8.1.6 examples 5-1 to 5-3: the arrow drawn in MCS, in a PCS turned 45 degrees, and
-- on three workpieces MCS -> OFFSET -> WCSn -> PCS.
local gid = 0
local function ArrowMotion()
  LineAbs2D(gid, 10, 10); LineAbs2D(gid, 110, 10); LineAbs2D(gid, 100, 40)
  Circle2D(gid, 60, 60, 40, 100, 0)
  LineAbs2D(gid, 10, 110); LineAbs2D(gid, 10, 10)
end
UngrpAllAxes(gid)
Enable(0); Enable(1)
Till(function() return IsEnabled(0) and IsEnabled(1) end)
SetupGroup(gid, 0, 1)                             -- axis 0 = X, axis 1 = Y
SetGrpMotionProfile(gid, 1000, 20000, 20000, 10)
ArrowMotion(); Till(function() return IsGrpInPos(gid) end)

-- Example 5-1: PCS {400, 200, 0, 0, 0, 45}.
SetGrpCoordTrans(gid, CS_PCS, {400, 200, 0, 0, 0, 45})
SetGrpCoordSys(gid, CS_PCS)
LineAbs2D(gid, 10, 10); Till(function() return IsGrpInPos(gid) end)
local _, mcs = GetGrpPoseCmd(gid, CS_MCS)
local _, pcs = GetGrpPoseCmd(gid, CS_PCS)
Print("5-1: PCS (%.3f, %.3f) is MCS (%.3f, %.3f)", pcs[1], pcs[2], mcs[1], mcs[2])

-- Examples 5-2 and 5-3: the same arrow on three workpieces, shifted by the offset.
local transfer = {100, 50, 0, 0, 0, 45}
SetGrpCoordTrans(gid, CS_PCS, transfer)
SetGrpCoordTrans(gid, CS_WCS1, {400, 400, 0, 0, 0, 0})
SetGrpCoordTrans(gid, CS_WCS2, {600, 0, 0, 0, 0, 0})
SetGrpCoordTrans(gid, CS_WCS3, {800, -400, 0, 0, 0, 0})
SetGrpCoordTrans(gid, CS_OFFSET, {0, -100, 0, 0, 0, 0})
for n, wcs in ipairs({CS_WCS1, CS_WCS2, CS_WCS3}) do
  SetGrpCoordSys(gid, CS_OFFSET | wcs | CS_PCS)
  ArrowMotion()
  Till(function() return IsGrpInPos(gid) end)
  _, mcs = GetGrpPoseCmd(gid, CS_MCS)
  Print("5-3: arrow %d ends at MCS (%.3f, %.3f)", n, mcs[1], mcs[2])
end
SetGrpCoordSys(gid, CS_MCS); LineAbs2D(gid, 0, 0); Till(function() return IsGrpInPos(gid) end)
local zeros = {0, 0, 0, 0, 0, 0}
for _, cs in ipairs({CS_PCS, CS_WCS1, CS_WCS2, CS_WCS3, CS_OFFSET}) do SetGrpCoordTrans(gid, cs, zeros) end
local _, t = GetGrpCoordTrans(gid, CS_PCS)
Print("PCS reset to {%g, %g, %g, %g, %g, %g}; coord sys %d", t[1], t[2], t[3], t[4], t[5], t[6], GetGrpCoordSys(gid))
Print("chapter 8 coordinates done")
