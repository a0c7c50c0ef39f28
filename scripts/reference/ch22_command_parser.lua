-- HMPL 22.2.1, example 2: the user ASCII agent's command parser, ported to Lua with the
-- manual's string functions. C's `&cmd[token_start]` is `cmd:sub(token_start + 1)`; the
-- response the C parser writes into `res` is its return value. Valid commands: "ENABLE 0",
-- "MOVEABS 0  0.05", "MOVEREL 0  0.01", "STOP 0".

--- Splits `cmd` into at most 3 tokens at spaces and carries out the command they name.
--- Returns the response (the command's return code, or "?" for no command) and the tokens.
function AsciiAgent(cmd)
  local token_str = {}
  local token_start, token_num = 0, 0
  for i = 1, 3 do
    local rest = cmd:sub(token_start + 1)
    local token_len = StrFindChar(rest, " ")
    local _, token = StringCopyEx(rest, 0, token_len)
    token_str[i] = token
    token_num = token_num + 1
    if token_len > 0 then
      local space_len = StrFindCharEx(rest:sub(token_len + 1), " ", true)
      token_start = token_start + token_len + space_len
    else
      token_start = -1
    end
    if token_start < 0 then break end
  end
  local token2_value, token3_value = 0, 0
  if token_num >= 2 then
    token2_value = StringToDouble(token_str[2])
    if token_num >= 3 then token3_value = StringToDouble(token_str[3]) end
  end
  local rc
  if IsStringEqual(token_str[1], "ENABLE") then
    if token_num == 2 then rc = Enable(token2_value) end
  elseif IsStringEqual(token_str[1], "MOVEABS") then
    if token_num == 3 then rc = MoveAbs(token2_value, token3_value) end
  elseif IsStringEqual(token_str[1], "MOVEREL") then
    if token_num == 3 then rc = MoveRel(token2_value, token3_value) end
  elseif IsStringEqual(token_str[1], "STOP") then
    if token_num == 2 then rc = Stop(token2_value) end
  end
  return rc and tostring(rc) or "?", token_str
end

-- The manual's commands, one after the other, as a client would send them.
local axis = 0
for _, command in ipairs({ "ENABLE 0", "MOVEABS 0  0.05", "MOVEREL 0  0.01", "STOP 0" }) do
  local response, tokens = AsciiAgent(command)
  Print("%-17s -> [%s] response %s", '"' .. command .. '"', table.concat(tokens, "|"), response)
  if command == "ENABLE 0" then Till(function() return IsEnabled(axis) end) end
  Till(function() return IsInPos(axis) end)
end
Print("axis 0 at %.3f mm", GetPosFb(axis))
Print("%s: response %s", '"JUMP 0 1"', (AsciiAgent("JUMP 0 1")))
Print("chapter 22 parser done")
