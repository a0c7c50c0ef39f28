-- HMPL chapter 3: strings and memory, each example of the manual with what it prints.
-- C's out-parameters come back after the return code (`rc, destination`); the strings
-- and tables passed in are never changed.

-- 3.2 Print
local str, var1, var2 = "hello world", 321, 1428.57
Print("var1: %d, var2: %f, str: %s", var1, var2, str) -- var1: 321, var2: 1428.570000, str: hello world
Print("var2: %e", var2) -- var2: 1.428570e+03
Print("var2: %g", var2) -- var2: 1428.57

-- 3.3 StringPrint
local n, dest = StringPrint("var1: %d, var2: %f, str: %s", var1, var2, str)
Print("%s", dest)
n, dest = StringPrint("var2: %e", var2)
Print("%s", dest)
n, dest = StringPrint("var2: %g", var2)
Print("%s (%d characters)", dest, n)

-- 3.4 StringLen, 3.5 IsStringEqual
Print("len = %d", StringLen(str)) -- 11
Print("is_equal = %d", IsStringEqual("hello world", "hello world")) -- 1
Print("is_equal = %d", IsStringEqual("hello world", "hello worldd")) -- 0

-- 3.6 StrFindChar
Print("StrFindChar h %d, l %d, z %d", StrFindChar(str, "h"), StrFindChar(str, "l"), StrFindChar(str, "z"))
-- 3.7 StrFindCharEx
Print("StrFindCharEx %d %d %d %d", StrFindCharEx(str, "lo ", false), StrFindCharEx(str, "lo ", true),
  StrFindCharEx(str, "zx!c", false), StrFindCharEx(str, "leh", true))
-- 3.8 StrFindStr
Print("StrFindStr hel %d, wor %d, wol %d", StrFindStr(str, "hel"), StrFindStr(str, "wor"), StrFindStr(str, "wol"))

-- 3.9 StringCopy, 3.10 StringCopyEx
local rc, destination = StringCopy("hello world")
Print("%s", destination) -- hello world
rc, destination = StringCopyEx("hello world", 6, 3)
Print("%s", destination) -- wor
rc, destination = StringCopyEx("hello world", 6, -1)
Print("%s", destination) -- world
rc, destination = StringCopyEx("hello world", 0, -1)
Print("%s", destination) -- hello world

-- 3.11 StringCat, 3.12 StringCatEx
rc, destination = StringCat("hello", " world")
Print("%s", destination) -- hello world
local source = "friendsmy "
rc, destination = StringCatEx("hello ", source, 7, -1)
Print("[%s]", destination) -- hello my
rc, destination = StringCatEx(destination, source, 0, 7)
Print("%s", destination) -- hello my friends

-- 3.13 StringToDouble
Print("v = %g", StringToDouble("1.234"))

-- HMPL_STR_MAX_LEN: a string may not grow past 512 characters.
rc, destination = StringCat(string.rep("x", 500), string.rep("y", 13))
Print("StringCat past HMPL_STR_MAX_LEN (%d): 0x%04X, destination kept (%d)", HMPL_STR_MAX_LEN, rc, StringLen(destination))

-- 3.14 MemoryCopy: tables of integers are C int arrays (4 bytes an element).
local function ints(t) return table.concat(t, ", ") end
local array1 = {1, 2, 3, 4, 5}
local array2 = {11, 22, 33, 44, 55}
local array3 = {345, 456, 567, 678, 789}
rc, array1 = MemoryCopy(array1, array2, 4 * #array2)
Print("array1: %s", ints(array1)) -- 11, 22, 33, 44, 55
rc, array1 = MemoryCopy(array1, array3, 4 * 3)
Print("array1: %s", ints(array1)) -- 345, 456, 567, 44, 55
-- C's &array1[3]: the tail as a table of its own.
local rc_tail, tail = MemoryCopy({table.unpack(array1, 4)}, {table.unpack(array3, 4)}, 4 * 2)
table.move(tail, 1, #tail, 4, array1)
Print("array1: %s", ints(array1)) -- 345, 456, 567, 678, 789

-- 3.15 MemorySet
array1 = {1, 2, 3, 4, 5}
rc, array1 = MemorySet(array1, 0, 4 * #array1)
Print("array1: %s", ints(array1)) -- 0, 0, 0, 0, 0
rc, array1 = MemorySet(array1, 1, 4)
Print("array1: %s (0x%08X)", ints(array1), array1[1]) -- 16843009, 0, 0, 0, 0

-- 3.16 IsMemoryEqual
array1, array2 = {1, 2, 3, 4, 5}, {1, 2, 3, 44, 55}
Print("is_equal = %s", tostring(IsMemoryEqual(array1, array2, 4 * #array2))) -- false
Print("is_equal = %s", tostring(IsMemoryEqual(array1, array2, 4 * 3))) -- true
Print("chapter 3 done")
