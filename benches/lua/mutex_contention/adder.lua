for i = 1, 25000 do
  MutexLock(0)
  system_user_table[0] = system_user_table[0] + 1
  MutexUnlock(0)
end
