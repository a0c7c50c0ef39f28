-- Four tasks add 1 to system_user_table[0] 25 000 times each under mutex 0.
system_user_table[0] = 0
local t0 = system_timeInMs
for t = 1, 4 do StartTask(t) end
Till(function() return IsTaskStop(1) and IsTaskStop(2) and IsTaskStop(3) and IsTaskStop(4) end)
Print("total %d in %d ms", system_user_table[0], system_timeInMs - t0)
