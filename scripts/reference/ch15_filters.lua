-- HMPL chapter 15 on ch15_filters.toml: axis 0 carries a flexible load ringing at 8 Hz.
-- The manual's two examples, then the filters at work on that load.

-- Example 1 (HMPL 15.1.1): the axis' input shaper, at the default 5.5 Hz and 0.03.
Print("example 1: SetAxisInShape %d, EnableAxisInShape %d", SetAxisInShape(0, 5.5, 0.03, SHAPER_NORMAL), EnableAxisInShape(0))
-- HMPL 15.1: VSF and InShape are never on together.
Print("EnableAxisVsf with InShape on: 0x%08X", EnableAxisVsf(0))
DisableAxisInShape(0)

Enable(0); Enable(1)
Till(function() return IsEnabled(0) and IsEnabled(1) end)

-- One 50 mm move; the time it takes, and the time the motor takes to settle after it.
local function move(label)
  MoveRel(0, 50)
  Till(function() return not IsMoving(0) end)
  Till(function() return IsInPos(0) end)
  Sleep(300)
  Print("%s: move %.0f ms", label, GetMoveTime(0))
  return GetMoveTime(0)
end

local plain = move("no filter")
SetAxisInShape(0, 8.0, 0.02, SHAPER_NORMAL)        -- tuned to the load: ZV, impulses 62.5 ms apart
EnableAxisInShape(0)
local shaped = move("ZV at 8 Hz")
Print("the shaper adds %.0f ms: half the load's period (62.5 ms) in whole cycles", shaped - plain)
SetAxisInShape(0, 8.0, 0.02, SHAPER_ROBUST)        -- ZVD: a whole period
shaped = move("ZVD at 8 Hz")
Print("the robust shaper adds %.0f ms: the load's period (125 ms) in whole cycles", shaped - plain)

MoveRel(0, 50)
Print("SetAxisInShape while moving: 0x%08X", SetAxisInShape(0, 9.0, 0.02, SHAPER_NORMAL))
Print("DisableAxisInShape while moving: 0x%08X", DisableAxisInShape(0))
Till(function() return not IsMoving(0) end)
DisableAxisInShape(0)

-- The VSF: a notch at the load's frequency.
Print("SetAxisVsf %d, EnableAxisVsf %d", SetAxisVsf(0, 8.0, 1.0), EnableAxisVsf(0))
Print("EnableAxisInShape with VSF on: 0x%08X", EnableAxisInShape(0))
Print("the notch's tail adds %.0f ms", move("VSF at 8 Hz") - plain)
DisableAxisVsf(0)
Print("SetAxisVsf(0, 0.05, 1.0): 0x%08X, SetAxisVsf(0, 10, 0.5): 0x%08X", SetAxisVsf(0, 0.05, 1.0), SetAxisVsf(0, 10, 0.5))
Print("SetAxisInShape(0, 1.0, 0.03, 1): 0x%08X", SetAxisInShape(0, 1.0, 0.03, 1))

-- Example 2 (HMPL 15.1.1): the group's input shaper.
local gid = 0
local axis1 = 0
local axis2 = 1
AddAxisToGrp(gid, axis1)
AddAxisToGrp(gid, axis2)
EnableGroup(gid)
Print("example 2: SetGrpInShape %d, EnableGrpInShape %d", SetGrpInShape(gid, 10, 0.15, 1), EnableGrpInShape(gid))
local _, before = GetGrpPoseCmd(gid, CS_MCS)
LineRel2D(gid, 20, 10)
Print("EnableGrpInShape while moving: 0x%08X", EnableGrpInShape(gid))
Till(function() return IsGrpInPos(gid) end)
local _, pose = GetGrpPoseCmd(gid, CS_MCS)
Print("the shaped line moved by (%.3f, %.3f)", pose[1] - before[1], pose[2] - before[2])
Print("SetGrpInShape(gid, 2.0, 0.1, 1): 0x%08X", SetGrpInShape(gid, 2.0, 0.1, 1))
UngrpAllAxes(gid)
Print("chapter 15 done")
