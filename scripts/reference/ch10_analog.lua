-- HMPL chapter 10, analog I/O, on the machine of ch10_analog.toml: slave 0 is axis 0's
-- drive, slave 1 an analog terminal whose output 1 is wired to its input 1, slave 2 one
-- whose input 1 the simulator drives.

-- Example 1 (10.1.1): set and read an output's raw value. The manual's slave 0 is slave 1
-- here (slave 0 is a drive); its "%l" has no conversion, "%ld" prints the long.
do
  local slv_id = 1
  local ao_index = 1            -- analog output channel
  local ao_raw_val = 0xFFFF     -- raw output value: 0xFFFF = 65535
  SetSlvAORaw(slv_id, ao_index, ao_raw_val)
  Print("%ld", GetSlvAORaw(slv_id, ao_index))
end
Sleep(5)                        -- one frame to the terminal and back

-- Example 2: read an input's raw value (wired to the output above).
do
  local slv_id = 1
  local ai_index = 1            -- analog input channel
  Print("%d", GetSlvAIRaw(slv_id, ai_index))
end

-- Example 3: conversion types. The manual prints GetSlvAI(slv_id, ...) with an undeclared
-- slv_id; the input's slave slv_id_ai is meant. The simulator puts 49152 on it (5 V).
SimSetSlvAIRaw(2, 1, 49152)
Sleep(5)
do
  local slv_id_ao = 1
  local ao_index = 1            -- analog output channel
  local slv_id_ai = 2
  local ai_index = 1            -- analog input channel

  SetSlvAOType(slv_id_ao, ao_index, HMPL_DAC_N10_P10)   -- output converted as -10..10
  SetSlvAO(slv_id_ao, ao_index, 10)                     -- output 10
  SetSlvAIType(slv_id_ai, ai_index, HMPL_DAC_N10_P10)   -- input converted as -10..10
  Print("%f", GetSlvAI(slv_id_ai, ai_index))
  Print("output %f raw %d", GetSlvAO(slv_id_ao, ao_index), GetSlvAORaw(slv_id_ao, ao_index))

  -- reset
  SetSlvAO(slv_id_ao, ao_index, 0)
  SetSlvAOType(slv_id_ao, ao_index, HMPL_DAC_NONE)
  SetSlvAIType(slv_id_ai, ai_index, HMPL_DAC_NONE)
  Print("reset: types %d %d, output raw %d", GetSlvAOType(slv_id_ao, ao_index), GetSlvAIType(slv_id_ai, ai_index),
    GetSlvAORaw(slv_id_ao, ao_index))
end

-- Table 10.1.1: a 16-bit +-10 V input, unsigned and then signed.
local function rows(range_type, raws)
  SetSlvAIType(2, 1, range_type)
  local out = {}
  for _, raw in ipairs(raws) do
    SimSetSlvAIRaw(2, 1, raw)
    Sleep(5)
    out[#out + 1] = string.format("%d->%.4f", GetSlvAIRaw(2, 1), GetSlvAI(2, 1))
  end
  Print("%s", table.concat(out, " "))
end
rows(HMPL_DAC_N10_P10, {65535, 49152, 32768, 16384, 0})
rows(HMPL_DAC_SIGNED | HMPL_DAC_N10_P10, {32767, 16384, 0, -16384, -32768})
SetSlvAIType(2, 1, HMPL_DAC_NONE)

-- 10.4: output 1 of slave 1 follows axis 0's reference position (AO = pos * 0.5 + 1).
SetSlvAOType(1, 1, HMPL_DAC_N10_P10)
SetSlvAOMonitor(1, 1, HMPL_AXIS_0 | HMPL_REF_POS)
SetSlvAOParam(1, 1, 1, 0.5, 1)
Print("bound %d, scale %.1f, offset %.1f", IsSlvAOBound(1, 1), GetSlvAOScale(1, 1), GetSlvAOOffset(1, 1))
Enable(0) Till(function() return IsEnabled(0) end)
MoveAbs(0, 8) Till(function() return IsInPos(0) end)
Sleep(5)
Print("at %.3f mm the output is %.4f", GetRefPos(0), GetSlvAO(1, 1))
SetSlvAOParam(1, 1, 0, 1, 0)
Disable(0)
Print("unbound %d; chapter 10 done", IsSlvAOBound(1, 1))
