-- Fatek FBs-PLC FUN147 (MHSPO) on luamotion: the manual's program example, run by the
-- core every cycle on the group interpolator (docs/fun147.md).
-- Ps0-Ps3 are axes 0-3 of the built-in machine; 1 pulse = 0.001 mm, SPD in Hz = pulses/s.

-- The axes must be enabled: the box groups them itself (group 14 for Gp 0).
for axis = 0, 3 do Enable(axis) end
Till(function() return IsEnabled(0) and IsEnabled(1) and IsEnabled(2) and IsEnabled(3) end)

-- The step table, as WinProladder's multi-axis command table writes it, at R2000.
MHSPOLoad("R2000", [[
001 SPD 5000                    ; vector speed 5 kHz
    LIN ADR,500,400,300,200,Ut  ; Ps0 500, Ps1 400, Ps2 300, Ps3 200
    WAIT TIME,100               ; 1 s
    GOTO NEXT
002 SPD R1000                   ; speed in DR1000 (R1001:R1000)
    LIN ADR,D100,D200, , ,Ut    ; Ps0 by DD100, Ps1 by DD200, Ps2/Ps3 idle
    WAIT TIME,R500              ; R500 x 0.01 s
    GOTO NEXT
003 SPD R1002                   ; speed in DR1002
    LIN ADR,0,0,R300,R400,Ps    ; Ps2 by DR300, Ps3 by DR400
    WAIT X0                     ; until X0 is ON
    GOTO 1
    MEND
]])
SetPlcReg("DR1000", 8000)
SetPlcReg("DD100", -1000)       -- D101:D100 = 0xFFFF:0xFC18
SetPlcReg("DD200", 2500)
SetPlcReg("R500", 25)           -- 0.25 s
SetPlcReg("DR1002", 3000)
SetPlcReg("DR300", 1200)
SetPlcReg("DR400", -600)
Print("%s", MHSPOText("R2000"))

-- The box: Gp 0, table at R2000, WR at D0; EN M100, PAU M101, ABT M102; ACT M110, ERR M111, DN M112.
MHSPO(0, "R2000", "D0", "M100", "M101", "M102", "M110", "M111", "M112")
SetPlcReg("D0", 0)              -- WR+0 = 0: the next EN runs step 1
SetPlcRelay("M100", true)       -- EN
Till(function() return GetPlcRelay("M112") end)   -- DN: step 1's move is done
Print("step %d done at Ps0 %d Ps1 %d Ps2 %d Ps3 %d", GetPlcReg("D4062"),
  GetPlcReg("DD4088"), GetPlcReg("DD4090"), GetPlcReg("DD4092"), GetPlcReg("DD4094"))
SetPlcReg("D1", 0)              -- clear WR+1 (DN), as a rising-edge contact would
Till(function() return GetPlcReg("D4062") == 3 end)   -- step 3's pulses are out
Print("step 3 done at Ps0 %d Ps1 %d Ps2 %d Ps3 %d (%.3f %.3f %.3f %.3f mm), waiting for X0: %s",
  GetPlcReg("DD4088"), GetPlcReg("DD4090"), GetPlcReg("DD4092"), GetPlcReg("DD4094"),
  GetRefPos(0), GetRefPos(1), GetRefPos(2), GetRefPos(3), tostring(GetPlcReg("D1") & 0x200 ~= 0))
SetPlcRelay("X0", true)         -- step 3's WAIT X0: back to step 1
Till(function() return GetPlcReg("D0") == 1 end)
SetPlcRelay("X0", false)
Print("running step %d again, ERR %s", GetPlcReg("D0"), tostring(GetPlcRelay("M111")))
SetPlcRelay("M100", false)      -- EN = 0: stop at once (M1991 OFF)
Sleep(10)
Print("stopped: ACT %s, Ready M1992 %s", tostring(GetPlcRelay("M110")), tostring(GetPlcRelay("M1992")))
MHSPOFree(0)
