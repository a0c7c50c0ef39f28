-- HMPL chapter 13: touch probes latch the axis' position on an edge of the encoder index
-- (Z phase) or of an external signal (ch13_touch_probe.toml: axis 0 the index only,
-- axis 1 both probes, its probe inputs at 30 and 35 mm, index marks every 10 mm).
local X, Y = 0, 1

local function expect(rc, what)
  if rc ~= 0 then error(string.format("%s failed: 0x%08X", what, rc), 2) end
end
local function move(axis, pos)
  expect(MoveAbs(axis, pos), "MoveAbs")
  Till(function() return IsInPos(axis) end)
end
local function b(flag) return flag and 1 or 0 end

for _, axis in ipairs({X, Y}) do expect(Enable(axis), "Enable") end
Till(function() return IsEnabled(X) and IsEnabled(Y) end)
move(X, 5) move(Y, 5)

-- 13.12 / 13.2: the Z phase (1), first event only (0), rising edge (0).
expect(SetTouchProbe1Func(X, 1, 0, 0), "SetTouchProbe1Func")
expect(EnableTouchProbe1(X), "EnableTouchProbe1")
Print("13.6/13.8: enabled %d, triggered %d", b(IsTouchProbe1Enabled(X)), b(IsTouchProbe1Triggered(X)))
move(X, 35)
local rc, pos = GetTouchProbe1Pos(X)
Print("13.10: single, rising: triggered %d, rc %d, %.4f mm", b(IsTouchProbe1Triggered(X)), rc, pos)

-- Continuous (1), falling edge (1): moving back, each pulse falls at its mark; the last wins.
expect(SetTouchProbe1Func(X, 1, 1, 1), "SetTouchProbe1Func")
move(X, 5)
rc, pos = GetTouchProbe1Pos(X)
Print("13.10: continuous, falling, moving back: rc %d, %.4f mm", rc, pos)

-- 13.4 / 13.6: switched off.
expect(DisableTouchProbe1(X), "DisableTouchProbe1")
Print("13.4: enabled %d, triggered %d", b(IsTouchProbe1Enabled(X)), b(IsTouchProbe1Triggered(X)))

-- 13.1 note 1: limited by the drive: axis 0's drive has no probe 2 and no external input.
Print("13.3 on axis 0: 0x%08X; external input on axis 0: 0x%08X", EnableTouchProbe2(X), SetTouchProbe1Func(X, 0, 0, 0))

-- Both probes of axis 1 at once: probe 1 on the external signal, probe 2 on the Z phase,
-- continuous, rising.
expect(SetTouchProbe1Func(Y, 0, 0, 0), "SetTouchProbe1Func")
expect(SetTouchProbe2Func(Y, 1, 1, 0), "SetTouchProbe2Func")
expect(EnableTouchProbe1(Y), "EnableTouchProbe1")
expect(EnableTouchProbe2(Y), "EnableTouchProbe2")
move(Y, 45)
local rc1, pos1 = GetTouchProbe1Pos(Y)
local rc2, pos2 = GetTouchProbe2Pos(Y)
Print("13.9/13.11: probe 1 %d at %.4f mm (rc %d), probe 2 %d at %.4f mm (rc %d)",
  b(IsTouchProbe1Triggered(Y)), pos1, rc1, b(IsTouchProbe2Triggered(Y)), pos2, rc2)

-- The position is in the axis' coordinates, as the feedback: SetPos moves it with them.
expect(SetPos(Y, 1000), "SetPos")
rc2, pos2 = GetTouchProbe2Pos(Y)
Print("after SetPos(1000) at 45 mm: probe 2 at %.4f mm", pos2)
expect(DisableTouchProbe1(Y), "DisableTouchProbe1")
expect(DisableTouchProbe2(Y), "DisableTouchProbe2")
Print("chapter 13 done")
