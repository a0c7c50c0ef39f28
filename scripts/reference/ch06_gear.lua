-- HMPL chapter 6, example 6.1.2 on the built-in machine's 4 axes: master 0 drives slaves
-- 1, 2 and 3 with ratios 1, 2 and -1.
local target = 100
local gear_ratio = {1.0, 2.0, -1.0}
local master = 0
local slave = {1, 2, 3}

Enable(master)
for _, s in ipairs(slave) do Enable(s) end
Till(function()
  for _, s in ipairs(slave) do if not IsEnabled(s) then return false end end
  return IsEnabled(master)
end)

for i, s in ipairs(slave) do
  local rc = EnableGear(master, s)                -- link (both axes enabled)
  if rc ~= 0 then error(string.format("EnableGear: 0x%08X", rc)) end
end
for i, s in ipairs(slave) do
  GearIn(master, s, gear_ratio[i])                -- engage
end

MoveAbs(master, target)
Till(function() return IsInPos(master) end)
Sleep(20)
for i, s in ipairs(slave) do
  Print("slave %d (ratio %.1f, in gear %s) at %.3f mm", s, GetGearRatio(s), tostring(IsInGear(s)), GetPosFb(s))
end

for _, s in ipairs(slave) do GearOut(s) end       -- disengage: the slaves stay where they are
for _, s in ipairs(slave) do DisableGear(s) end   -- unlink: independent axes again
Print("master %s, slave %s: chapter 6 done", tostring(IsGearMaster(master)), tostring(IsGearSlave(slave[1])))
