-- ascii_jog.lua: jog axes from any terminal through the User ASCII server (HMPL 22.2.1).
-- Commands, one a line: "JOG+ <axis>", "JOG- <axis>" (move at JOG_VEL until stopped),
-- "STOP <axis>", "POS <axis>" (the feedback position). Answers: "OK", the position, or
-- "ERROR ...". Try it: `luamotion run scripts/examples/ascii_jog.lua`, then
-- `nc 127.0.0.1 4000` and type `JOG+ 0`, `POS 0`, `STOP 0`.
local JOG_VEL = 20 -- mm/s

local function jog(axis, vel)
  if not IsEnabled(axis) then
    return "ERROR axis " .. axis .. " is not enabled"
  end
  local rc = MoveVel(axis, vel)
  if rc ~= 0 then
    return string.format("ERROR 0x%08X", rc)
  end
  return "OK"
end

local commands = {
  ["JOG+"] = function(axis) return jog(axis, JOG_VEL) end,
  ["JOG-"] = function(axis) return jog(axis, -JOG_VEL) end,
  ["STOP"] = function(axis)
    local rc = Stop(axis)
    return rc == 0 and "OK" or string.format("ERROR 0x%08X", rc)
  end,
  ["POS"] = function(axis) return string.format("%.4f", GetPosFb(axis)) end,
}

-- The parser: one command line in, one answer out (HMPL's `void Parser(char *cmd, char *res)`).
local function parser(line)
  local name, axis = line:match("^%s*(%S+)%s+(%d+)%s*$")
  local command = name and commands[name:upper()]
  if not command then
    return "ERROR unknown command: " .. line
  end
  axis = tonumber(axis)
  if axis >= GetAxisNum() then
    return "ERROR no axis " .. axis
  end
  return command(axis)
end

Till(IsSystemOper)
for axis = 0, GetAxisNum() - 1 do
  Enable(axis)
end
Till(function()
  for axis = 0, GetAxisNum() - 1 do
    if not IsEnabled(axis) then
      return false
    end
  end
  return true
end)
local rc = START_ASCII_AGENT(parser)
if rc ~= 0 then
  Print("another task runs the ASCII agent (0x%X)", rc)
end
-- The agent serves its clients after the program's end, until the task is stopped.
