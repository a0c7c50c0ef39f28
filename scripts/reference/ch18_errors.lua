-- HMPL chapter 18: error codes. Axis errors are 0x83IIEEEE (II = axis), group errors
-- 0x82IIEEEE, system errors 0x0000EEEE; the eERR_* constants hold the EEEE part.
local axis = 2

local function show(what, code)
  Print("%-28s 0x%08X", what, code)
end

-- A disabled axis refuses motion: the code is returned and kept as the last error.
local rc = MoveAbs(axis, 10)
show("MoveAbs on a disabled axis", rc)
if GetAxisLastErr(axis) & 0xFFFF == eERR_AXIS_CMD_INVALID_DISABLED then
  Print("that is eERR_AXIS_CMD_INVALID_DISABLED on axis %d", (GetAxisLastErr(axis) >> 16) & 0xFF)
end
ClearAxisLastErr(axis)
show("after ClearAxisLastErr", GetAxisLastErr(axis))

-- A setting out of range.
Enable(axis) Till(function() return IsEnabled(axis) end)
SetVelScale(axis, 120)
show("SetVelScale(120)", GetAxisLastErr(axis))

-- A drive fault (injected by the simulator): the axis is disabled, in ErrorStop.
SimDriveFault(axis, 0x2310)
Till(function() return not IsEnabled(axis) end)
show("drive fault", GetAxisLastErr(axis))
Print("the drive reports 0x%04X (0x603F); IsDriveErr %s", GetDriveErr(axis), tostring(IsDriveErr(axis)))
Reset(axis)
Till(function() return not IsDriveErr(axis) end)

-- A system error: an axis that does not exist.
MoveAbs(99, 0)
show("GetSystemLastErr", GetSystemLastErr())
show("GetGrpLastErr(0)", GetGrpLastErr(0))
Print("chapter 18 done")
