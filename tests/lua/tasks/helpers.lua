-- Entry points for the task checks: task 0 starts them with StartTaskFunc. The top level
-- only declares, as a program meant for StartTaskFunc should.
function Counter()
  task_vars.runs = (task_vars.runs or 0) + 1
  system_ltest9 = task_vars.runs
end

function TakeMutex0()
  MutexLock(0)
  system_ltest0 = 1
  MutexUnlock(0)
end

function HoldMutex1()
  MutexLock(1)
  system_ltest1 = 1
  Till(function() return false end)
end

function TakeMutex1()
  MutexLock(1)
  system_ltest2 = 1
end

function LockTwice()
  MutexLock(5)
  MutexLock(5)
  Print("never printed: the second MutexLock stops the task")
end

function Forever()
  Till(function() return 0 end)
end

function Move()
  Enable(1) Till(function() return IsEnabled(1) end)
  MoveAbs(1, 1000)
  Till(function() return false end)
end
