-- HMPL chapter 12 on ch12_position_trigger.toml: the manual's two examples on axis 1,
-- whose drive has a position trigger wired to GPO 1, and the preconditions.
local axis_id = 1

-- The pulses of the last pass: how many, and where.
local function report(label)
  local n = GetPTPulseNum(axis_id)
  local at = {}
  for i = 0, n - 1 do
    local _, pos = GetPTPulse(axis_id, i)
    at[#at + 1] = string.format("%g", pos)
  end
  Print("%s: %d pulses at %s, %d missed", label, n, table.concat(at, " "), GetPTMissedNum(axis_id))
end

-- Refused: an axis whose drive has no trigger (0x1451), an axis not homed (0x83II0064).
Print("EnablePT on axis 0: 0x%X", EnablePT(0))
Print("EnablePT before homing: 0x%X", EnablePT(axis_id))

-- Example 1: equidistant PT, 10 to 20 mm every 1 mm.
local start_pos, end_pos, interval = 10, 20, 1
SetPT_PulseWidth(axis_id, 1000)
Enable(axis_id) Till(function() return IsEnabled(axis_id) end)
SetHomeMethod(axis_id, HOME_METHOD_33)
MoveHome(axis_id) Till(function() return IsHomed(axis_id) end)
Print("homed at %.3f mm", GetPosFb(axis_id))
-- Positive direction.
SetPT_StartPos(axis_id, start_pos)
SetPT_Interval(axis_id, interval)
SetPT_EndPos(axis_id, end_pos)
EnablePT(axis_id)
Print("IsPTEnabled %s", tostring(IsPTEnabled(axis_id)))
MoveAbs(axis_id, 30) Till(function() return IsInPos(axis_id) end)
report("example 1 forward")
Print("IsPTEnabled %s", tostring(IsPTEnabled(axis_id)))
-- Negative direction: start above the end.
SetPT_StartPos(axis_id, end_pos)
SetPT_EndPos(axis_id, start_pos)
EnablePT(axis_id)
MoveAbs(axis_id, 0.0) Till(function() return IsInPos(axis_id) end)
report("example 1 backward")

-- Example 2: non-equidistant PT over the position array (the manual passes 0 for the
-- axis to the array functions; its axis is axis_id).
local pos = {10, 12, 13, 16, 17, 20, 22, 25, 26, 28, 30}
for i = 0, 10 do SetPT_PosArray(axis_id, i, pos[i + 1]) end
SetPT_StartIndex(axis_id, 0)
SetPT_EndIndex(axis_id, 10)
EnablePT(axis_id)
MoveAbs(axis_id, 40) Till(function() return IsInPos(axis_id) end)
report("example 2 forward")
SetPT_StartIndex(axis_id, 10)
SetPT_EndIndex(axis_id, 0)
EnablePT(axis_id)
MoveAbs(axis_id, 0.0) Till(function() return IsInPos(axis_id) end)
report("example 2 backward")

-- The state words: points 1 and 4 (12 and 17 mm) give no pulse.
SetPT_StateArray(axis_id, 0, 0x7FF & ~((1 << 1) | (1 << 4)))
SetPT_StartIndex(axis_id, 0)
SetPT_EndIndex(axis_id, 10)
EnablePT(axis_id)
MoveAbs(axis_id, 40) Till(function() return IsInPos(axis_id) end)
report("states 0x7ED forward")

-- Arguments out of range: 0x83II012C.
Print("width 10 ns: 0x%X, 1010 ns: 0x%X; index 256: 0x%X; state word 8: 0x%X; interval 0: 0x%X",
  SetPT_PulseWidth(axis_id, 10), SetPT_PulseWidth(axis_id, 1010), SetPT_PosArray(axis_id, 256, 1),
  SetPT_StateArray(axis_id, 8, 1), SetPT_Interval(axis_id, 0))
Print("chapter 12 done")
