-- HMPL ch. 6 (gear) and ch. 7 (gantry), on the built-in machine.
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
local function enable(a) Enable(a) Till(function() return IsEnabled(a) end) end
local function settle(a) Till(function() return IsInPos(a) end) end

-- HMPL ch. 6: master 0 drives slaves 1 (ratio 2) and 2 (ratio -1).
check(EnableGear(0, 1) == 0x83000078, "51: both must be enabled")
enable(0) enable(1) enable(2)
check(GearIn(0, 1, 2.0) == 0x83010FA0, "GearIn before EnableGear: 0x83II0FA0")
check(EnableGear(0, 1) == 0 and EnableGear(0, 2) == 0, "51: linked")
check(IsGearSlave(1) and IsGearMaster(0) and IsSync(1) and not IsInGear(1), "51: slave, master, sync")
check(GearIn(0, 1, 2.0) == 0 and GearIn(0, 2, -1.0) == 0, "51: engaged")
check(GetGearRatio(1) == 2.0 and IsInGear(1), "51: ratio 2")
check(MoveAbs(1, 5) == 0x830100A0, "a slave takes no motion of its own")
MoveAbs(0, 100)
settle(0)
Sleep(50)
check(math.abs(GetPosFb(1) - 200) < 0.02 and math.abs(GetPosFb(2) + 100) < 0.02, "51: +200 and -100")
check(GearOut(1) == 0 and not IsInGear(1), "51: GearOut")
MoveAbs(0, 0) settle(0)
check(math.abs(GetPosFb(1) - 200) < 0.02, "a disengaged slave stays")
check(DisableGear(1) == 0 and DisableGear(2) == 0 and not IsGearMaster(0), "unlinked")

-- HMPL ch. 7: gantry pair 2 (right-hand) and 3 (left-hand).
Disable(2) Till(function() return not IsEnabled(2) end)
enable(3)
check(EnableGantryPair(2, 3) == 0x8303006E, "52: refused while an axis is enabled")
Disable(3) Till(function() return not IsEnabled(3) end)
check(GetGantryPairID(2) == -1, "52: not a gantry axis: -1")
check(EnableGantryPair(2, 3) == 0, "52: paired")
check(IsGantry(2) and IsGantry(3) and IsGantryPair(2, 3) and GetGantryPairID(2) == GetGantryPairID(3), "52: one pair")
check(GetGantryPairID(2) >= 0 and not IsGantryPair(1, 2), "52: ids")
check(not IsEnabled(3), "52: the left-hand axis starts disabled")
Enable(2)
local deadline = system_timeInMs + 1000
Till(function() return (IsEnabled(2) and IsEnabled(3)) or system_timeInMs > deadline end)
check(IsEnabled(2) and IsEnabled(3), "52: enabling one enables both")
MoveAbs(2, 40) settle(2)     -- linear
MoveAbs(3, 5) settle(3)      -- yaw
local r, l = ReadPDO(2, 0x6064, 0) / 10000, ReadPDO(3, 0x6064, 0) / 10000
check(math.abs(r - 45) < 0.02 and math.abs(l - 35) < 0.02, "52: R = 45, L = 35")
check(math.abs(GetPosFb(2) - (r + l) / 2) < 0.02 and math.abs(GetPosFb(3) - (r - l) / 2) < 0.02, "52: linear and yaw")
check(DisableGantryPair(2) == 0x8302006E, "split only while disabled")
Disable(2)
Till(function() return not IsEnabled(2) and not IsEnabled(3) end)
check(DisableGantryPair(3) == 0 and not IsGantry(2), "52: split")
Print("gear and gantry facts passed")
