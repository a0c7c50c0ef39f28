-- HMPL ch. 2, 11, 16, 19 and 23.2 (system, user table, tasks, keywords), task 0 of machine.toml.
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
local function hex(v) return string.format("0x%X", v) end
local function within(ms, cond)
  local deadline = system_timeInMs + ms
  Till(function() return cond() or system_timeInMs > deadline end)
  return cond()
end
local function stopped(t) return function() return IsTaskStop(t) end end

-- HMPL 16.1, 16.2: 64 tasks; a running task cannot be started again.
check(StartTask(64) == 0x0107 and StartTask(-1) == 0x0107, "5: task ids 0..63 (0x0107)")
check(StartTask(7) == 0x010A, "16.2: no program configured (0x010A)")
check(StartTaskFunc(1, "Forever") == 0, "16.3: started at a function")
check(StartTask(1) == 0x0108 and StartTaskFunc(1, "Counter") == 0x0108, "5: running (0x0108)")

-- HMPL 16.3: a function the program does not have.
check(StartTaskFunc(2, "NoSuchFunc") == 0x0109, "6: 0x0109, got " .. hex(StartTaskFunc(2, "NoSuchFunc")))

-- HMPL 16.6: stopped before, running while, stopped after main returns or StopTask.
check(IsTaskStop(3), "7: stopped before it starts")
check(not IsTaskStop(1), "7: running")
check(StopTask(1) == 0 and IsTaskStop(1), "7: stopped after StopTask")
check(StopTask(1) == 0x010B, "16.4: not running (0x010B)")
check(StartTaskFunc(3, "Counter") == 0 and within(1000, stopped(3)), "7: stopped after its function returns")

-- HMPL 2.22, 2.23: MutexLock blocks while another task holds the mutex, until it is unlocked...
system_ltest0 = 0
MutexLock(0)
StartTaskFunc(2, "TakeMutex0")
Sleep(100)
check(system_ltest0 == 0, "9: task 2 waits for mutex 0")
MutexUnlock(0)
check(within(1000, function() return system_ltest0 == 1 end), "9: task 2 has it once task 0 unlocks")
-- ...or the owner stops; an unlock by another task does nothing.
system_ltest1, system_ltest2 = 0, 0
StartTaskFunc(4, "HoldMutex1")
check(within(1000, function() return system_ltest1 == 1 end), "task 4 holds mutex 1")
MutexUnlock(1)
StartTaskFunc(5, "TakeMutex1")
Sleep(100)
check(system_ltest2 == 0, "9: MutexUnlock by a non-owner does nothing")
StopTask(4)
check(within(1000, function() return system_ltest2 == 1 end), "9: released when the owner stops")
-- Locking twice stops the task (0x13EC, see the test's log).
check(StartTaskFunc(6, "LockTwice") == 0 and within(1000, stopped(6)), "9: a second MutexLock stops the task")

-- HMPL 2.18: Sleep(100) waits 100 cycles of 1 ms (more only when the OS wakes us late).
local c = system_fclk
Sleep(100)
check(system_fclk - c >= 100 and system_fclk - c < 150, "10: Sleep(100), got " .. (system_fclk - c))

-- HMPL 19.3: Till returns at the first evaluation that holds; Till(0) never returns.
local target = system_fclk + 50
local held = 0
Till(function()
  if system_fclk >= target then held = held + 1 end
  return system_fclk >= target
end)
check(held == 1, "12: returned as soon as the condition held")
StartTaskFunc(2, "Forever")
Sleep(300)
check(not IsTaskStop(2), "12: Till(0) never returns")
StopTask(2)

-- HMPL 2.24, 2.25: TON and TOF on controller time.
-- On a loaded machine a task may miss cycles between two calls, so what is checked is the
-- edge: the output false at every call before 100 ms from the timer's start, true at the
-- first call after. Each call happens between the clock's reads before and after it.
local t = TimerInit()
local before, after, last_false, rose
Till(function()
  local read_before = system_timeInMs
  local q = TON(t, true, 100)
  local read_after = system_timeInMs
  if not before then before, after = read_before, read_after end
  if q then rose = read_after else last_false = read_before end
  return q
end)
check(rose - before >= 100 and last_false - after < 100,
  "13: TON after 100 ms, got " .. (rose - before) .. " (last false at " .. (last_false - before) .. ")")
check(TON(t, false, 100) == false and t.ET == 0, "13: TON falls with IN and resets")
local off = TimerInit()
check(TOF(off, 1, 100), "13: TOF is on as soon as IN is")
local fell_before = system_timeInMs
TOF(off, 0, 100)
local fell_after = system_timeInMs
local last_on, dropped = fell_before, nil
Till(function()
  local read_before = system_timeInMs
  local q = TOF(off, 0, 100)
  local read_after = system_timeInMs
  if q then last_on = read_before else dropped = read_after end
  return not q
end)
check(dropped - fell_before >= 100 and last_on - fell_after < 100,
  "13: TOF 100 ms after IN fell, got " .. (dropped - fell_before) .. " (last on at " .. (last_on - fell_before) .. ")")

-- HMPL 1.5: a task's variables keep their values when it runs again.
StartTaskFunc(3, "Counter")
check(within(1000, stopped(3)) and system_ltest9 == 2, "14: the second run counts 2, got " .. system_ltest9)

-- HMPL 2.19, 2.20: messages up to 128 characters; events throttled to about 1000 per second.
check(SendMsgEvent("%s", string.rep("x", 128)) == 0, "15: 128 characters")
check(SendMsgEvent("%s", string.rep("x", 129)) == 0x138D, "15: 129 refused (0x138D)")
local t0 = system_timeInMs
for i = 1, 1500 do SendEvent(i) end
local took = system_timeInMs - t0
check(took >= 1390 and took < 3000, "15: 1500 events take 1.4 s after a burst of 100, took " .. took)

-- HMPL 2.1-2.5, 2.8, 2.7: system state, StopAll, DisableAll.
check(GetECATSt() == 8 and IsSystemOper(), "28: EtherCAT in Op")
Enable(0) Till(function() return IsEnabled(0) end)
SetBufferMode(0, 1)
MoveAbs(0, 50) MoveAbs(0, 0) MoveAbs(0, 50)
Sleep(100)
check(StopAll() == 0, "2.8: StopAll")
check(within(100, function() return not IsMoving(0) end), "30: stopped with the kill deceleration")
check(IsEnabled(0) and GetCmdNum(0) == 0, "30: still enabled, queue cleared")
MoveAbs(0, 10)
check(DisableAll() == 0, "2.7: DisableAll")
check(within(100, function() return not IsEnabled(0) end) and GetCmdNum(0) == 0, "31: disabled, plans cleared")

-- HMPL ch. 11: the user table, by function and by index.
check(SetUserTable(1, 5, {-2, 0, 2, 6, 4}) == 0, "11.2")
local rc, out = GetUserTable(3, 3)
check(rc == 0 and out[1] == 2 and out[2] == 6 and out[3] == 4, "11.3: {2, 6, 4}")
check(system_user_table[4] == 6 and GetTableValue(5) == 4, "11.1: the same memory")
system_user_table[511999] = 1.5
check(GetTableValue(511999) == 1.5 and SetTableValue(512000, 1) == 0x138F, "11.4/11.5")
check(SetTableValue(3, 2) == 0 and SaveUserTable(3, 3) == 0, "11.6")
SetUserTable(3, 3, {999, 777, 888})
check(LoadUserTable(3, 3) == 0 and GetTableValue(4) == 6, "11.7: loaded back")
system_mtest[9] = 0.25
system_dtest3 = 2.5
check(system_mtest[9] == 0.25 and system_dtest3 == 2.5 and #system_mtest == 10, "23.2")
check(_TASKID_ == 0, "19.1: _TASKID_")
Print("task facts passed")
