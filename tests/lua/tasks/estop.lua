-- HMPL 2.9: EStop stops every task and disables every axis.
Enable(0) Till(function() return IsEnabled(0) end)
StartTaskFunc(1, "Move")
Till(function() return IsMoving(1) end)
Print("before EStop")
EStop()
Print("never printed: EStop stopped this task")
