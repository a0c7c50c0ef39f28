-- HMPL chapter 14 on the built-in machine's 4 axes: the manual's three examples of
-- dynamic error compensation (14.1.1), each set up, enabled, observed while its
-- reference axes move, and disabled the manual's way. The axes count as homed
-- (SetHomedStatus): compensation needs fixed coordinates (HMPL 14.1).
for a = 0, 3 do
  SetHomedStatus(a, 1)
  SetVel(a, 1000) SetAcc(a, 10000) SetDec(a, 10000)
end
local function on(a) Enable(a) Till(function() return IsEnabled(a) end) end
local function off(a) Disable(a) Till(function() return not IsEnabled(a) end) end
local function move(a, pos) MoveAbs(a, pos) Till(function() return IsInPos(a) end) end
local function settled(a) Sleep(3) Till(function() return IsInPos(a) end) end

-- Example 1: one dimension. Axis 0 compensated from axis 1's position.
do
  local data = {-0.2, 0.1, -0.3, 0.4, -0.1}
  SetUserTable(1, 5, data)
  SetupComp(0,    -- compensated axis
            1,    -- user table start index
            -100, -- base position
            200,  -- interval
            5,    -- number of points (with the base): -100 .. 700
            1)    -- reference axis
  EnableComp(0)
  Enable(0)       -- enabling axis 0 activates the compensation
  Till(function() return IsEnabled(0) end)
  Print("example 1: compensation active %s", tostring(IsCompActive(0)))
  on(1)
  for _, x in ipairs({-100, 0, 100, 550, 800}) do
    move(1, x) settled(0)
    Print("example 1: axis 1 at %6.1f -> compensation %.4f, position output - reference %.4f",
          GetRefPos(1), GetCompPos(0), GetPosOut(0) - GetRefPos(0))
  end
  -- Disabling: the reference becomes the present position.
  Disable(0)
  Till(function() return not IsEnabled(0) end)
  DisableComp(0)
  Sleep(3)
  Print("example 1: disabled, active %s, compensation %.4f, reference at the drive's position %s",
        tostring(IsCompActive(0)), GetCompPos(0), tostring(math.abs(GetRefPos(0) - GetPosFbComp(0)) < 1e-9))
  move(1, 0)
end

-- Example 2: two dimensions. Axis 2 compensated from axes 0 and 1 (the Z of an XYZ table).
do
  local data = {0.3, 0.1, -0.4, -0.4, 0.0, 0.2, 0.2, -0.1, 0.5}
  SetUserTable(3, 9, data)
  local base = {-100, -100}
  local interval = {200, 100}
  local num_pt = {3, 3}
  local ref_axis = {0, 1}
  SetupComp2D(2, 3, base, interval, num_pt, ref_axis)
  EnableComp(2)
  Enable(2)
  Till(function() return IsEnabled(2) end)
  on(0)
  for _, p in ipairs({{-100, -100}, {100, 0}, {0, 50}, {300, 200}}) do
    move(0, p[1]) move(1, p[2]) settled(2)
    Print("example 2: axes 0, 1 at (%.0f, %.0f) -> compensation %.4f", GetRefPos(0), GetRefPos(1), GetCompPos(2))
  end
  off(2)
  DisableComp(2)
end

-- Example 3: three dimensions. Axis 2 compensated from axes 0, 1 and itself; three
-- 3 x 3 tables, one for each position of axis 2.
do
  local data = {0.3, 0.1, 0.2, -0.2, 0.0, 0.1, -0.1, 0.3, 0.4,    -- table 1
                0.2, -0.1, 0.4, 0.2, 0.0, 0.2, 0.3, 0.1, 0.1,    -- table 2
                0.4, 0.3, -0.2, -0.2, 0.1, 0.2, -0.2, 0.1, -0.4} -- table 3
  SetUserTable(3, 27, data)
  local base = {-10, 5, 0}
  local interval = {20, 10, 30}
  local num_pt = {3, 3, 3}
  local ref_axis = {0, 1, 2}
  SetupComp3D(2, 3, base, interval, num_pt, ref_axis)
  Print("example 3: cubic spline on a 3-D table: 0x%08X", SetCompAlgType(2, 1))
  EnableComp(2)
  Enable(2)
  Till(function() return IsEnabled(2) end)
  for _, p in ipairs({{10, 15, 30}, {30, 25, 60}, {0, 10, 15}}) do
    move(0, p[1]) move(1, p[2]) move(2, p[3]) settled(2)
    Print("example 3: axes 0, 1, 2 at (%.0f, %.0f, %.0f) -> compensation %.4f", GetRefPos(0), GetRefPos(1),
          GetRefPos(2), GetCompPos(2))
  end
  Print("example 3: SetPos while compensating: 0x%08X", SetPos(2, 0))
  off(2)
  DisableComp(2)
end

-- The limit: 1 mm by default (HMPL 14.1, 0x83II0802).
SetUserTable(100, 2, {0.0, 1.2})
off(0) off(1)
SetupComp(3, 100, 0, 100, 2, 1)
EnableComp(3)
on(3) on(1)
move(1, 100)
Print("limit: error stop %s, compensation %.4f, last error 0x%08X", tostring(IsErrorStop(3)), GetCompPos(3),
      GetAxisLastErr(3))
Print("chapter 14 done")
