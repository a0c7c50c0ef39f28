-- HMPL 9.1, 9.2.6: the E-stop input.
local function check(cond, what)
  if not cond then error("FAILED: " .. what, 2) end
end
Enable(0) Till(function() return IsEnabled(0) end)
StartTaskFunc(1, "Move")
Till(function() return IsMoving(1) end)
check(BindEMO(0) == 0, "9.2.6: no E-stop input")
SimSetGPI(8, 1)
Sleep(20)
check(IsEnabled(1) and not IsTaskStop(1) and GetGPI(8) == 1, "32: BindEMO(0): GPI 8 stops nothing")
SimSetGPI(8, 0)
check(BindEMO(9) == -1 and GetAllGPI() == 0, "9.2.6: inputs 1..8; 9.4.3")
check(BindEMO(3) == 0, "9.2.6: GPI 3")
Print("raising GPI 3")
SimSetGPI(3, 1)
Sleep(1000)
Print("never printed: the E-stop stopped this task")
