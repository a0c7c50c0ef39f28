-- freeport_echo.lua: a DRL FreePort Ethernet echo server (DXMC 8.3 FreePort).
-- Listens on TCP port 9000 (127.0.0.1; `[freeport] bind = "0.0.0.0"` in the machine file for all
-- interfaces), frames end with ";", and each frame comes back as "echo:<frame>;".
-- The frame "quit" ends the program. Try it: `nc 127.0.0.1 9000`, type `hi;`.
local PORT = 9000
local Dev1 = 1 -- the session id, any number the program chooses

local ret = FreePort.Eth.OpenAsServer(Dev1, PORT, nil, ";")
if ret ~= 0 then
  my_print(string.format("OpenAsServer failed: code %d", ret))
  return
end
my_print(string.format("echo server on port %d", PORT))

while true do
  -- Rx never waits: code 0 with a count of 0 means no whole frame yet.
  local rc, data, count = FreePort.Eth.Rx(Dev1)
  if rc == 0 and count > 0 then
    if data == "quit" then
      break
    end
    FreePort.Eth.Tx(Dev1, "echo:" .. data)
  elseif rc == 6 then
    my_print("a frame longer than 1024 bytes was dropped")
  end
  -- Code 5 (no peer) is normal: the next client is accepted on a later call.
  Sleep(1)
end

FreePort.Eth.Close(Dev1)
my_print("echo server done")
