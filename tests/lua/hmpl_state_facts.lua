-- HMPL 5.2 to 5.4 (axis settings and state) and ch. 18 (errors), on the built-in machine.
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
local function enable(a) Enable(a) Till(function() return IsEnabled(a) end) end
local function settle(a) Till(function() return IsInPos(a) end) end

-- HMPL 5.4.12, 18.7 (drive fault): disabled, IsDriveErr, 0x83II03F2, GetDriveErr = 0x603F.
enable(2)
SimDriveFault(2, 0x2310)
Till(function() return not IsEnabled(2) end)
check(IsDriveErr(2) and IsErrorStop(2) and GetAxisLastErr(2) == 0x830203F2, "44: drive fault")
check(GetDriveErr(2) == 0x2310, "18.7: the drive's code")
check(Enable(2) == 0x83020096, "no enable in ErrorStop")
check(SetPos(2, 0) == 0x83020096, "45: no SetPos in ErrorStop")
Reset(2)
Till(function() return not IsDriveErr(2) end)
enable(2)
check(IsEnabled(2), "enabled again after Reset")

-- HMPL 5.4.13 (position error): the drive held where it is while the axis moves on.
enable(3)
ForceWritePDO(3, 0x607A, 0, ReadPDO(3, 0x6064, 0))
MoveAbs(3, 20)
Till(function() return IsErrorStop(3) end)
ReleasePDO(3, 0x607A, 0)
check(IsPosErr(3) and GetAxisLastErr(3) == 0x8303083E, "44: position error 0x83II083E")
Till(function() return not IsEnabled(3) end)
Reset(3)

-- HMPL 5.3.19: SetPos moves the origin; refused for a gear slave.
local a = 1
enable(a)
MoveAbs(a, 37) settle(a)
check(SetPos(a, 0) == 0, "45: SetPos")
check(math.abs(GetPosFb(a)) < 0.01 and GetRefPos(a) == 0 and GetPosOffset(a) == 37, "45: feedback 0, offset +37")
MoveAbs(a, 5) settle(a)
check(math.abs(GetPosFb(a) - 5) < 0.01, "moves in the new coordinates")
enable(0)
EnableGear(0, a)
check(SetPos(a, 1) == 0x830100A0, "45: refused for a gear slave (0x83II00A0)")
DisableGear(a)

-- HMPL 5.3.39, 5.3.40: rollover only while disabled; positions wrap; turns counted; shortest way.
check(SetRollover(a, 360) == 0x8301006E, "46: refused while enabled")
check(SetRollover(a, -1) ~= 0 and GetAxisLastErr(a) == 0x830101F4, "46: negative refused")
Disable(a) Till(function() return not IsEnabled(a) end)
check(SetRollover(a, 360) == 0, "46: accepted while disabled")
enable(a)
MoveRel(a, 725) settle(a)
check(math.abs(GetPosFb(a) - 10) < 0.01 and GetRolloverTurns(a) == 2, "46: 730 reads 10, 2 turns")
MoveAbs(a, 350) settle(a)
check(math.abs(GetPosFb(a) - 350) < 0.01 and GetRolloverTurns(a) == 1, "46: to 350 the short way back")
Disable(a) Till(function() return not IsEnabled(a) end)
SetRollover(a, 0)
enable(a)

-- HMPL 5.3.41: op modes 8, 9, 10.
for _, m in ipairs({8, 9, 10}) do local r = SetOpMode(a, m) check(r == 0, string.format("47: mode %d, got 0x%X", m, r)) end
check(SetOpMode(a, 7) ~= 0 and GetAxisLastErr(a) == 0x830100FA, "47: 7 refused")
check(MoveAbs(a, 1) == 0x830100F0, "no position move in cst")
check(MoveTrq(a, 0.5) == 0, "5.2.7: a torque in cst")
Sleep(50)
check(math.abs(GetCurrFb(a)) > 0, "5.3.26: current feedback")
MoveTrq(a, 0)
SetOpMode(a, 8)
Stop(a)

-- HMPL 5.3.42, 5.3.44: buffer mode 1 queues; mode 0 replaces; no change while commands wait.
SetPos(a, 0)
check(SetBufferMode(a, 1) == 0 and GetBufferMode(a) == 1, "48: buffer mode 1")
MoveAbs(a, 10) MoveAbs(a, 20) MoveAbs(a, 30)
check(GetCmdNum(a) == 2, "48: two waiting")
check(SetBufferMode(a, 0) == 0x83010105, "48: 0x83II0105 with commands waiting")
Till(function() return GetCmdNum(a) == 0 end)
settle(a)
check(GetRefPos(a) == 30, "48: ran in order to 30")
SetBufferMode(a, 0)
MoveAbs(a, 100)
Sleep(100)
MoveAbs(a, -10)
settle(a)
check(GetRefPos(a) == -10 and GetCmdNum(a) == 0, "48: mode 0 replaced the move")

-- HMPL 5.2.8: at most 50 PVT points; the manual's kind of table runs.
local t, p, v = {}, {}, {}
for i = 1, 51 do t[i] = (i - 1) * 10 p[i] = -10 v[i] = 0 end
check(MovePVT(a, t, p, v, 51) ~= 0, "49: 51 points refused")
check(MovePVT(a, {0, 1000, 2000}, {-10, 0, 10}, {0, 20, 0}, 3) == 0, "5.2.8: PVT accepted")
Till(function() return not IsMoving(a) end)
check(GetRefPos(a) == 10, "ends on the last point")
check(MovePVT(a, {0, 100}, {10, 100}, {0, 0}, 2) == 0x830108AC, "PVT acceleration limit")

-- HMPL 18.1, 18.4: error code layout, ClearAxisLastErr.
check(GetAxisLastErr(a) >> 24 == 0x83 and (GetAxisLastErr(a) >> 16) & 0xFF == a, "91")
check(ClearAxisLastErr(a) == 0 and GetAxisLastErr(a) == 0, "92")
check(GetGrpLastErr(0) == 0 and ClearGrpLastErr(15) == 0, "18.5/18.6: no group has failed")
check(MoveAbs(99, 0) == 0x138F and GetSystemLastErr() == 0x138F, "18.2: the last system error")
check(GetAxisNum() == 4, "5.3.36")
Print("state facts passed")
