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

    /// Reads a drive object by SDO. Returns its value (sign-extended), or -1 on failure
    /// (ambiguous with a real -1, as in HMPL; use `ReadSDOEx` to tell them apart).
    ["HMPL 17.2.1", ascii] fn ReadSDO(slv_id: Int, obj_index: Int, obj_subindex: Int, obj_length: Int) -> Int;
    /// Reads a drive object by SDO: `rc, bytes` with rc 0 or -1 and the object's bytes as a
    /// table of integers (little-endian).
    ["HMPL 17.2.2"] fn ReadSDOEx(slv_id: Int, obj_index: Int, obj_subindex: Int, obj_length: Int) -> (Int, Bytes);
    /// Writes a drive object by SDO. Returns 0, or -1 on failure.
    ["HMPL 17.2.3", ascii] fn WriteSDO(slv_id: Int, obj_index: Int, obj_subindex: Int, obj_length: Int, obj_value: Int) -> Int;
    /// Writes a drive object by SDO from bytes (a table of integers or a string). Returns 0 or -1.
    ["HMPL 17.2.4"] fn WriteSDOEx(slv_id: Int, obj_index: Int, obj_subindex: Int, obj_length: Int, obj_value: Bytes) -> Int;
    /// Writes an object mapped in the RxPDO. The motion kernel may overwrite it in the same
    /// cycle if it writes that object too. Returns 0 or -1.
    ["HMPL 17.2.7", ascii] fn WritePDO(slv_id: Int, obj_index: Int, obj_subindex: Int, obj_value: Int) -> Int;
    /// Forces an RxPDO object: the value overrides every other writer until `ReleasePDO`.
    ["HMPL 17.2.8", ascii] fn ForceWritePDO(slv_id: Int, obj_index: Int, obj_subindex: Int, obj_value: Int) -> Int;
    /// Releases a forced RxPDO object. Returns 0 or -1.
    ["HMPL 17.2.9", ascii] fn ReleasePDO(slv_id: Int, obj_index: Int, obj_subindex: Int) -> Int;

    /// Simulator only: puts a drive into Fault with an error code of the CoE manual's table
    /// 4-16 (e.g. 0x3110 over voltage). Returns 0, or -1 for a code the drive model lacks.
    ["luamotion sim"] fn SimDriveFault(slv_id: Int, error_code: Int) -> Int;
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

    /// Reads an object mapped in the process data (TxPDO or RxPDO). Returns its value, or -1
    /// when it is not mapped.
    ["HMPL 17.2.5", ascii] fn ReadPDO(slv_id: Int, obj_index: Int, obj_subindex: Int) -> Int;
    /// Reads a mapped object: `rc, bytes` with rc 0 or -1.
    ["HMPL 17.2.6"] fn ReadPDOEx(slv_id: Int, obj_index: Int, obj_subindex: Int) -> (Int, Bytes);

    /// True while the controller is initialising (never, once scripts run).
    ["HMPL 2.1", ascii] fn IsSystemInit() -> Bool;
    /// True when the system runs and EtherCAT is in Op: motion and PDO functions work.
    ["HMPL 2.2", ascii] fn IsSystemOper() -> Bool;
    /// True when the system runs with EtherCAT in Pre-Op (mailbox only).
    ["HMPL 2.3", ascii] fn IsSystemPreOp() -> Bool;
    /// True when the system is in error, e.g. EtherCAT start-up stopped short of Op.
    ["HMPL 2.4", ascii] fn IsSystemError() -> Bool;
    /// The master's EtherCAT state: 1 Init, 2 Pre-Op, 4 Safe-Op, 8 Op.
    ["HMPL 2.5", ascii] fn GetECATSt() -> Int;
    /// A slave's EtherCAT state: 1, 2, 4 or 8 (-1 for no such slave).
    ["HMPL 2.6", ascii] fn GetSlvECATSt(slv_id: Int) -> Int;
    /// The number of slaves on the network.
    ["HMPL 2.10", ascii] fn GetSlaveNum() -> Int;
    /// Channels of a slave (`slv_id | HMPL_SLOT_n`) by type: 1 digital inputs, 2 digital
    /// outputs, 3 analog inputs, 4 analog outputs (-1 for no such slave or type).
    ["HMPL 21.1", ascii] fn GetSlvChNum(slv_slot_id: Int, ch_type: Int) -> Int;
    /// The number of slots (modules) of a slave; a drive has none.
    ["HMPL 21.2", ascii] fn GetSlvSlotNum(slv_id: Int) -> Int;
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
