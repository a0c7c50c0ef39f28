//! The declarations: every function a script can call, with the manual's names and
//! argument order. Section numbers are those of the HMPL manual (MH06UC01-2510) and of
//! the DXMC manual's DRL chapter.

use crate::registry::declare_functions;

declare_functions! {
    Command, COMMANDS;

    /// Enables (servo on) the axis by walking the drive's CiA 402 state machine.
    /// Returns at once; `Till(function() return IsEnabled(a) end)` waits for the drive.
    ["HMPL 5.2.1", ascii] fn Enable(axis_id: Int) -> Int;
    /// Disables (servo off) the axis and clears its path planning.
    ["HMPL 5.2.2", ascii] fn Disable(axis_id: Int) -> Int;
    /// Moves to an absolute position (mm or deg) with the axis' velocity, acceleration and
    /// deceleration. A move while moving re-plans to the new target.
    ["HMPL 5.2.4", ascii] fn MoveAbs(axis_id: Int, pos: Double) -> Int;
    /// Moves by a distance relative to the current command position.
    ["HMPL 5.2.5", ascii] fn MoveRel(axis_id: Int, rel_dist: Double) -> Int;
    /// Sets the profile velocity (mm/s or deg/s, > 0).
    ["HMPL 5.3.2", ascii] fn SetVel(axis_id: Int, vel: Double) -> Int;
    /// Sets the profile acceleration (mm/s² or deg/s², > 0).
    ["HMPL 5.3.4", ascii] fn SetAcc(axis_id: Int, acc: Double) -> Int;
    /// Sets the profile deceleration (mm/s² or deg/s², > 0).
    ["HMPL 5.3.7", ascii] fn SetDec(axis_id: Int, dec: Double) -> Int;
}

declare_functions! {
    Query, QUERIES;

    /// True when the axis is enabled (drive in Operation enabled).
    ["HMPL 5.4.1", ascii] fn IsEnabled(axis_id: Int) -> Bool;
    /// True while the profile generator still emits new positions.
    ["HMPL 5.4.2", ascii] fn IsMoving(axis_id: Int) -> Bool;
    /// True when the feedback has stayed within the position window for the window time.
    ["HMPL 5.4.3", ascii] fn IsInPos(axis_id: Int) -> Bool;
    /// Position feedback (mm or deg).
    ["HMPL 5.3.20", ascii] fn GetPosFb(axis_id: Int) -> Double;
    /// Reference position: the profile generator's output (mm or deg).
    ["HMPL 5.3.27", ascii] fn GetRefPos(axis_id: Int) -> Double;
    /// The axis' last error as a 32-bit code `0x83IIEEEE` (0: none).
    ["HMPL 18.3", ascii] fn GetAxisLastErr(axis_id: Int) -> Int;
}

declare_functions! {
    Local, LOCALS;

    /// Suspends the task for `ms` milliseconds of controller time.
    ["HMPL 2.18"] fn Sleep(ms: Int);
    /// Suspends the task until `condition()` returns a true value (not false, nil or 0).
    /// The condition is evaluated once per controller cycle.
    ["HMPL 19.3"] fn Till(condition: Func);
    /// Writes a formatted line to the message window (`%d %i %u %x %c %s %f %e %g %%`).
    /// Returns the number of characters written.
    ["HMPL 3.2"] fn Print(format: Str, args: Rest) -> Int;
    /// DRL: writes a string to the program's console.
    ["DXMC 8.3 DRL"] fn my_print(text: Str);
    /// DRL: suspends the program for a number of seconds (fractions allowed) of controller time.
    ["DXMC 8.3 DRL"] fn DELAY(seconds: Double);
}
