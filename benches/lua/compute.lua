local t = {}
local x = 0
for i = 1, 20000000 do
  x = (x + i * 3) % 1000003
  t[i % 1024 + 1] = x
  if x < 0 then
    x = 0 -- @never
  end
end
local function f(a, b)
  return a * b + 1
end
local s = 0
for i = 1, 5000000 do
  s = f(s % 1000, i) % 1000003
end
return x + s
