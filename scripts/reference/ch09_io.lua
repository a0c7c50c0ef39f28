-- HMPL ch. 9: the controller's digital I/O and a slave's, with the manual's examples.
-- The simulator plays the wiring: SimSetGPI and SimSetSlvGPI switch inputs as sensors would.

-- HMPL 9.1: indices are 1-based, bit idx-1 of a mask is pin idx.
SimSetGPI(1, 1)
SimSetGPI(4, 1)
Sleep(2)
Print("GetAllGPI with GPI 1 and 4 on: %d", GetAllGPI())          -- HMPL 9.4.3: 9
SetGPO(2, 1)
SetGPO(3, 1)
Print("GetAllGPO with GPO 2 and 3 on: %d", GetAllGPO())          -- HMPL 9.4.4: 6
SimSetGPI(1, 0)
SimSetGPI(4, 0)
SetAllGPO(0)
Sleep(2)

-- Example 1 (HMPL 9.1.2): a rising edge on GPI 4 disables every axis and sets GPO 3.
Enable(0)
Till(function() return IsEnabled(0) end)
local last_state = 0
local rising = 0
for cycle = 1, 20 do
  if cycle == 5 then SimSetGPI(4, 1) end
  local input = GetGPI(4)
  if (input ~ last_state) & input ~= 0 then
    DisableAll()
    SetGPO(3, 1)
    rising = cycle
  end
  last_state = input
  Sleep(1)
end
Till(function() return not IsEnabled(0) end)
Print("example 1: rising edge seen %s, axis 0 enabled %s, GPO 3 = %d", tostring(rising > 0), tostring(IsEnabled(0)), GetGPO(3))
SimSetGPI(4, 0)
SetAllGPO(0)

-- Example 2 (HMPL 9.1.2): a falling edge on slave 1's input 3 toggles its output 2 and
-- switches every controller output on.
SimSetSlvGPI(1, 3, 1)
Sleep(2)
last_state = GetSlvGPI(1, 3)
for cycle = 1, 20 do
  if cycle == 5 then SimSetSlvGPI(1, 3, 0) end
  local input = GetSlvGPI(1, 3)
  if (input ~ last_state) ~= 0 and input == 0 then
    ToggleSlvGPO(1, 2)
    SetAllGPO(0xff)
  end
  last_state = input
  Sleep(1)
end
Print("example 2: slave 1 output 2 = %d, controller outputs 0x%X", GetSlvGPO(1, 2), GetAllGPO())

-- HMPL 9.5.3-9.5.6: masks of a slave's pins, from pin 1 or from a start index.
SimSetSlvGPI(1, 1, 1)
SimSetSlvGPI(1, 4, 1)
SimSetSlvGPI(1, 8, 1)
SimSetSlvGPI(1, 11, 1)
SetSlvAllGPO(1, 0)
SetSlvGPO(1, 9, 1)
SetSlvGPO(1, 10, 1)
Sleep(2)
Print("GetSlvAllGPIByStartIdx(1, 8) with inputs 8 and 11 on: %d", GetSlvAllGPIByStartIdx(1, 8)) -- 9
Print("GetSlvAllGPOByStartIdx(1, 8) with outputs 9 and 10 on: %d", GetSlvAllGPOByStartIdx(1, 8)) -- 6
SetSlvAllGPO(1, 0x6)
Sleep(2)
Print("SetSlvAllGPO(1, 0x6): GetSlvAllGPO %d", GetSlvAllGPO(1))  -- HMPL 9.5.4: 6

-- HMPL 9.2.4, 9.2.5: inversion.
SetGPIInvert(2, 1)
SetGPOInvert(5, 1)
Sleep(2)
Print("inverted: GPI 2 reads %d, invert masks 0x%X 0x%X", GetGPI(2), GetAllGPIInvertSt(), GetAllGPOInvertSt())
SetGPIInvert(2, 0)
SetGPOInvert(5, 0)

-- HMPL 9.1: this chapter's failures are -1.
Print("GetGPI(9) %d, SetGPO(0, 1) %d, SetSlvGPO(1, 17, 1) %d, GetSlvGPI(5, 1) %d",
  GetGPI(9), SetGPO(0, 1), SetSlvGPO(1, 17, 1), GetSlvGPI(5, 1))
-- HMPL 9.1.2 example 3: a slot on a slave without slots.
Print("SetSlvGPO(1 | HMPL_SLOT_2, 3, 1) %d", SetSlvGPO(1 | HMPL_SLOT_2, 3, 1))
Print("chapter 9 done")
