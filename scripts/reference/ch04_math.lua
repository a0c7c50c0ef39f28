-- HMPL chapter 4: the math functions (C libm, radians) with the manual's examples and
-- what they print.
Print("sine of 30.0 degrees is %f.", sin(30.0 * PI / 180)) -- 0.5
Print("cosine of 60.0 degrees is %f.", cos(60.0 * PI / 180)) -- 0.5
Print("tangent of 45.0 degrees is %f.", tan(45.0 * PI / 180)) -- 1
Print("arc sine of 0.5 is %f degrees", asin(0.5) * 180.0 / PI) -- 30
Print("arc cosine of 0.5 is %f degrees", acos(0.5) * 180.0 / PI) -- 60
Print("arc tangent of 1.0 is %f degrees", atan(1.0) * 180.0 / PI) -- 45
Print("arc tangent for (x=-10, y=10) is %f degrees", atan2(10, -10) * 180.0 / PI) -- 135
Print("absolute value of -3591 is %d.", abs(-3591))
Print("absolute value of -35.91 is %f.", fabs(-35.91))
Print("ceil of 2.3 is %g", ceil(2.3)) -- 3
Print("ceil of 3.8 is %g", ceil(3.8)) -- 4
Print("ceil of -2.3 is %g", ceil(-2.3)) -- -2
Print("ceil of -3.8 is %g", ceil(-3.8)) -- -3
Print("floor of 2.3 is %g", floor(2.3)) -- 2
Print("floor of 3.8 is %g", floor(3.8)) -- 3
Print("floor of -2.3 is %g", floor(-2.3)) -- -3
Print("floor of -3.8 is %g", floor(-3.8)) -- -4
Print("0.95 * 2^4 = %f", ldexp(0.95, 4)) -- 15.2
Print("The exponential value of 5.0 is %f.", exp(5.0)) -- 148.413159
Print("7.0 ^ 3.0 = %f", pow(7.0, 3.0)) -- 343
Print("4.73 ^ 12.0 = %f", pow(4.73, 12.0)) -- 125410439.217423
Print("32.01 ^ 1.54 = %f", pow(32.01, 1.54)) -- 208.036691
Print("log(5.5) = %f", log(5.5)) -- 1.704748
Print("log10(1000.0) = %f", log10(1000.0)) -- 3
Print("sqrt(1024.0) = %f", sqrt(1024.0)) -- 32
Print("cbrt (27.0) = %f", cbrt(27.0)) -- 3
Print("hypot(3.0, 4.0) = %f.", hypot(3.0, 4.0)) -- 5
-- HMPL 4.12-4.14: a result too large is the largest double.
Print("exp(1000) is the largest double: %s", tostring(exp(1000) == 1.7976931348623157e308))
Print("pow(10, 400) = %g, ldexp(1, 5000) = %g", pow(10, 400), ldexp(1, 5000))
-- HMPL 23.1: the math constants.
Print("PI %.17g SQRT2 %.17g SQRT1_2 %.17g", PI, SQRT2, SQRT1_2)
-- HMPL 23.3: the bit macros are Lua's operators.
local bits_value = 0
bits_value = bits_value | (1 << 0) -- BIT_SET(bits_value, 0): 1
bits_value = bits_value | (1 << 3) -- BIT_SET(bits_value, 3): 9
local set = bits_value
bits_value = bits_value & ~(1 << 0) -- BIT_CLEAR(bits_value, 0): 8
local cleared = bits_value
bits_value = bits_value ~ (1 << 4) -- BIT_FLIP(bits_value, 4): 24
Print("bits: %d %d %d", set, cleared, bits_value)
bits_value = 684
if bits_value & (1 << 5) ~= 0 then Print("bit 5 is 1") else Print("bit 5 is 0") end
Print("chapter 4 done")
