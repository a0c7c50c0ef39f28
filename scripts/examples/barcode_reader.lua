-- barcode_reader.lua: reads codes from serial port 1 as a barcode scanner sends them,
-- each ended by CR LF (DXMC 8.3 FreePort), until the code "END". Each code is printed,
-- counted in DV word 0x0010 (Modbus clients read the count there), and acknowledged to
-- the scanner with "OK <n>".
-- Try it: `luamotion run scripts/examples/barcode_reader.lua` prints the port
-- (`serial port 1: /dev/pts/N`); then, in another shell,
--   printf 'A123\r\nB456\r\nEND\r\n' | socat - /dev/pts/N,raw,echo=0,b38400
local COUNT_WORD = 0x0010

-- 8,N,1 FreePort, no start byte, CR LF at the end; the buffer starts empty.
local rc, format = FreePort.Serial.Init(1, nil, CR_LF, 0x17)
if rc ~= 0 then
  my_print(string.format("Init failed: code %d", rc))
  return
end
my_print(string.format("reading codes on serial port 1 (format word 0x%08X)", format))
WriteModbusWord(COUNT_WORD, 0)

local count = 0
while true do
  -- Rx never waits: code 0 with a count of 0 means no whole code yet.
  local rc, code, n = FreePort.Serial.Rx(1)
  if rc == 0 and n > 0 then
    if code == "END" then
      break
    end
    count = count + 1
    WriteModbusWord(COUNT_WORD, count)
    my_print(string.format("code %d: %s", count, code))
    FreePort.Serial.Tx(1, "OK " .. count)
  elseif rc == 6 then
    my_print("a code longer than 256 bytes was dropped")
  elseif rc == 11 then
    my_print("line error: set the scanner to 8,N,1 at 38400 baud")
  elseif rc ~= 0 then
    my_print(string.format("Rx: code %d", rc))
  end
  Sleep(5)
end
my_print(string.format("%d codes read", count))
