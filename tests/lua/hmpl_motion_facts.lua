-- HMPL 5.1 to 5.3 (axis motion and settings), on axis 1 of the built-in machine.
local a = 1
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
local function settle() Till(function() return IsInPos(a) end) end

Enable(a)
Till(function() return IsEnabled(a) end)

-- HMPL 5.2.4: moving, then the profile ends on the target, then in position.
check(MoveAbs(a, 100) == 0 and IsMoving(a) and not IsInPos(a), "35: moving at once")
Till(function() return not IsMoving(a) end)
check(GetRefPos(a) == 100, "35: reference exactly 100")
settle()
check(GetMoveTime(a) > 1000 and GetSettlingTime(a) >= 0, "5.3.17/18: move and settling times")

-- HMPL 5.2.5: MoveRel from 100 by 10.
MoveRel(a, 10) settle()
check(GetRefPos(a) == 110, "36: 110")

-- HMPL 5.2.6, 5.2.9: MoveVel runs until Stop; then not moving and nothing queued.
check(MoveVel(a, -20) == 0, "37: MoveVel accepted")
Sleep(300)
check(IsMoving(a) and GetRefVel(a) == -20, "37: moving negative at 20")
check(MoveVel(a, 1e9) ~= 0 and GetAxisLastErr(a) == 0x83010140, "MoveVel above max_vel refused")
Stop(a)
check(MoveAbs(a, 0) == 0x8301008C, "a Stop decelerating refuses other motion (0x83II008C)")
Till(function() return not IsMoving(a) end)
check(GetCmdNum(a) == 0 and GetRefVel(a) == 0, "37: stopped, queue empty")
MoveAbs(a, 0) settle()

-- HMPL 5.2.10, 5.2.11: Halt stops short of the target; Resume carries on to it.
MoveAbs(a, 200)
Sleep(500)
Halt(a)
Till(function() return not IsMoving(a) end)
check(GetRefPos(a) < 200, "38: halted short of 200")
Resume(a)
settle()
check(GetRefPos(a) == 200, "38: resumed to 200")

-- HMPL 5.3: non-positive values are refused; the last valid one stays.
SetVel(a, 150)
for _, f in ipairs({SetVel, SetAcc, SetDec, SetKillDec, SetAccTime, SetDecTime, SetPosWindow, SetPosWindowTime}) do
  check(f(a, 0) ~= 0 and f(a, -1) ~= 0, "39: 0 and -1 refused")
end
check(GetVel(a) == 150, "39: GetVel keeps the last valid value")
check(SetAccTime(a, 100) == 0 and GetAcc(a) == 1500, "5.3.5: acc = vel / time")
SetAcc(a, 1000) SetDec(a, 1000) SetVel(a, 100)
check(SetKillDec(a, 20000) == 0 and GetKillDec(a) == 20000, "5.3.9/10")

-- HMPL 5.3.16: smooth time 0..500 ms, not while moving.
check(SetSMTime(a, 501) ~= 0 and GetAxisLastErr(a) == 0x83010168, "40: 501 refused (0x83II0168)")
check(SetSMTime(a, 100) == 0 and GetSMTime(a) == 100, "40: 100 accepted at rest")
MoveAbs(a, 0)
check(SetSMTime(a, 50) ~= 0 and GetAxisLastErr(a) == 0x83010082, "40: refused while moving")
settle()

-- HMPL 5.1: with Ts = 100 ms and A = 1000, the acceleration phase lasts v/A + Ts = 0.2 s,
-- and the jerk is A / Ts = 10 000 mm/s³. The phase is timed in controller cycles, from the
-- first cycle with a velocity (the first 1 ms sample of the move) to the first at 100 mm/s.
-- Till runs once per cycle, but a busy machine may let the program miss one, or stop it
-- between its reads. Each read takes the newest snapshot, so the velocity a sample reads
-- comes from a cycle between the cycle number read before it and the one read after: a
-- change first seen in a sample happened after the previous sample's first read and no
-- later than this sample's last; the phase's length is bounded so at both ends. The move
-- starts in a cycle after the one read before `MoveAbs`, and may already show in the
-- snapshot read just after it, before Till's first sample. A jerk sample counts only when
-- the cycle number is the same before and after its reads.
local before_move = system_fclk
MoveAbs(a, 100)
local peak_jerk, last_acc, last_cycle, last_before, first_cycle = 0, 0, system_fclk, before_move, nil
local last_consistent = nil
local start_slack, end_slack = 0, 0
Till(function()
  local before = system_fclk
  local acc, vel, cycle = GetRefAcc(a), GetRefVel(a), system_fclk
  local consistent = before == cycle
  if consistent and last_consistent and cycle > last_cycle then
    peak_jerk = math.max(peak_jerk, math.abs(acc - last_acc) / (0.001 * (cycle - last_cycle)))
  end
  last_consistent = consistent
  -- The change seen here happened in one of the cycles last_before + 1 .. cycle.
  local slack = math.max(0, cycle - last_before - 1)
  if vel > 0 and not first_cycle then first_cycle, start_slack = cycle, slack end
  end_slack = slack
  last_acc, last_cycle, last_before = acc, cycle, before
  return vel >= 100 - 1e-9
end)
local n = last_cycle - first_cycle + 1
local shortest, longest = n - end_slack, n + start_slack
check(shortest <= 201 and longest >= 199,
  "41: acceleration phase of 200 ms, got " .. n .. " (uncertain by " .. start_slack .. " cycles at the start, "
    .. end_slack .. " at the end)")
check(math.abs(peak_jerk - 10000) < 200, "41: jerk A/Ts, got " .. peak_jerk)
settle()
SetSMTime(a, 0)

-- HMPL 5.3.37: a velocity scale of 50 % halves the cruise velocity.
SetVelScale(a, 50)
MoveAbs(a, 0)
Sleep(500)
check(math.abs(GetRefVel(a) + 50) < 1e-9, "42: cruising at 50 mm/s")
check(SetVelScale(a, 101) ~= 0 and GetAxisLastErr(a) == 0x8301017C, "42: 101 refused")
check(GetVelScale(a) == 50, "42: GetVelScale")
SetVelScale(a, 100)
settle()

-- HMPL 5.3.11-14: a software limit stops the axis at or before it, in ErrorStop.
check(SetSWRL(a, 50) == 0 and GetSWRL(a) == 50, "5.3.11/12")
MoveAbs(a, 100)
Till(function() return IsErrorStop(a) end)
Till(function() return not IsMoving(a) end)
check(GetRefPos(a) <= 50 and IsSWRL(a), "43: stopped at or before 50, IsSWRL")
check(GetAxisLastErr(a) == 0x830107DA, "43: 0x83II07DA")
check(MoveAbs(a, 0) == 0x83010096, "motion refused in ErrorStop")
check(Reset(a) == 0 and not IsErrorStop(a) and not IsSWRL(a), "43: Reset clears ErrorStop")
IgnoreSWL(a, 1)
MoveAbs(a, 100) settle()
check(GetRefPos(a) == 100, "43: IgnoreSWL lets the move complete")
IgnoreSWL(a, 0)
SetSWRL(a, 1e9)
MoveAbs(a, 0) settle()
Print("motion facts passed")
