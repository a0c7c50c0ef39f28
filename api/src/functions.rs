//! The declarations: every function a script can call, with the manual's names and
//! argument order. Section numbers are those of the HMPL manual (MH06UC01-2510) and of
//! the DXMC manual's DRL chapter.

use crate::registry::declare_functions;

declare_functions! {
    Command, COMMANDS => CommandCall<'a>;

    // HMPL 5.2: axis motion control.
    /// Enables (servo on) the axis by walking the drive's CiA 402 state machine; both axes
    /// of a gantry pair. Returns at once; `Till(function() return IsEnabled(a) end)` waits.
    ["HMPL 5.2.1", ascii] fn Enable(axis_id: Int[Axis]) -> Int;
    /// Disables (servo off) the axis and clears its path planning.
    ["HMPL 5.2.2", ascii] fn Disable(axis_id: Int[Axis] as Changes) -> Int;
    /// Leaves ErrorStop once the cause is gone (a drive fault is reset too).
    ["HMPL 5.2.3", ascii] fn Reset(axis_id: Int[Axis]) -> Int;
    /// Moves to an absolute position (mm or deg) with the axis' profile. In buffer mode 0 a
    /// move under way is re-planned to the new target; in mode 1 it is queued.
    ["HMPL 5.2.4", ascii] fn MoveAbs(axis_id: Int[Axis] as Moves, pos: Double[Target]) -> Int;
    /// Moves by a distance from the target under way (or from the reference at rest).
    ["HMPL 5.2.5", ascii] fn MoveRel(axis_id: Int[Axis] as Moves, rel_dist: Double[Distance]) -> Int;
    /// Moves at a constant velocity until stopped; the sign is the direction.
    ["HMPL 5.2.6", ascii] fn MoveVel(axis_id: Int[Axis] as Moves, vel: Double[Velocity]) -> Int;
    /// Produces a constant torque (N·m) in cyclic synchronous torque mode (`SetOpMode(a, 10)`).
    ["HMPL 5.2.7", ascii] fn MoveTrq(axis_id: Int[Axis] as Moves, torque_cmd: Double[Torque]) -> Int;
    /// Moves through position-velocity-time points (times in ms from 0, at most 50 points),
    /// starting where the axis stands. The tables hold at least `num_pt` numbers each.
    ["HMPL 5.2.8"] fn MovePVT(axis_id: Int[Axis] as Moves, time: Doubles[PvtTime], pos: Doubles[Target], vel: Doubles[PvtVelocity], num_pt: Int) -> Int;
    /// Decelerates to a stop and clears the path planning.
    ["HMPL 5.2.9", ascii] fn Stop(axis_id: Int[Axis] as Moves) -> Int;
    /// Pauses the motion (velocity to 0), keeping it for `Resume`.
    ["HMPL 5.2.10", ascii] fn Halt(axis_id: Int[Axis] as Moves) -> Int;
    /// Continues a halted motion to its target.
    ["HMPL 5.2.11", ascii] fn Resume(axis_id: Int[Axis] as Moves) -> Int;

    // HMPL 5.3: axis settings.
    /// Sets the profile velocity (mm/s or deg/s, > 0, at most the machine file's `max_vel`).
    ["HMPL 5.3.2", ascii] fn SetVel(axis_id: Int[Axis], vel: Double[Speed]) -> Int;
    /// Sets the profile acceleration (mm/s² or deg/s², > 0, at most `max_acc`).
    ["HMPL 5.3.4", ascii] fn SetAcc(axis_id: Int[Axis], acc: Double[Acceleration]) -> Int;
    /// Sets the acceleration from a time (ms, > 0): acc = vel / time.
    ["HMPL 5.3.5", ascii] fn SetAccTime(axis_id: Int[Axis], acc_time: Double[AccTime]) -> Int;
    /// Sets the profile deceleration (> 0, at most `max_acc`).
    ["HMPL 5.3.7", ascii] fn SetDec(axis_id: Int[Axis], dec: Double[Deceleration]) -> Int;
    /// Sets the deceleration from a time (ms, > 0).
    ["HMPL 5.3.8", ascii] fn SetDecTime(axis_id: Int[Axis], dec_time: Double[DecTime]) -> Int;
    /// Sets the kill deceleration of StopAll and error stops (> 0).
    ["HMPL 5.3.10", ascii] fn SetKillDec(axis_id: Int[Axis], kill_dec: Double[KillDeceleration]) -> Int;
    /// Sets the software right (positive) limit.
    ["HMPL 5.3.12", ascii] fn SetSWRL(axis_id: Int[Axis], right_limit_pos: Double[Position]) -> Int;
    /// Sets the software left (negative) limit.
    ["HMPL 5.3.14", ascii] fn SetSWLL(axis_id: Int[Axis], left_limit_pos: Double[Position]) -> Int;
    /// Sets the smooth time (0..500 ms) that turns the profile into an S-curve; not while moving.
    ["HMPL 5.3.16", ascii] fn SetSMTime(axis_id: Int[Axis], smooth_time: Double[SmoothTime]) -> Int;
    /// Makes the present position read `pos` by moving the axis' origin; not while moving,
    /// synchronous, in a gantry or in error.
    ["HMPL 5.3.19", ascii] fn SetPos(axis_id: Int[Axis], pos: Double[Position]) -> Int;
    /// 1: ignore the hardware limits; 0: react to them (the default).
    ["HMPL 5.3.33", ascii] fn IgnoreHWL(axis_id: Int[Axis], cmd: Int) -> Int;
    /// 1: ignore the software limits; 0: react to them (the default).
    ["HMPL 5.3.34", ascii] fn IgnoreSWL(axis_id: Int[Axis], cmd: Int) -> Int;
    /// 1: ignore the position-error limit; 0: react to it (the default).
    ["HMPL 5.3.35", ascii] fn IgnorePE(axis_id: Int[Axis], cmd: Int) -> Int;
    /// Sets the velocity override, 0..100 %, applied to the move under way.
    ["HMPL 5.3.37", ascii] fn SetVelScale(axis_id: Int[Axis], vel_scale: Double[Percent]) -> Int;
    /// Sets the rollover length (> 0; 0 switches it off); only while disabled.
    ["HMPL 5.3.39", ascii] fn SetRollover(axis_id: Int[Axis], rollover_val: Double[Rollover]) -> Int;
    /// Sets the drive mode: 8 cyclic synchronous position, 9 velocity, 10 torque.
    ["HMPL 5.3.41", ascii] fn SetOpMode(axis_id: Int[Axis], op_mode: Int) -> Int;
    /// Sets the buffer mode: 0 a new move replaces the one under way, 1 moves queue up.
    ["HMPL 5.3.42", ascii] fn SetBufferMode(axis_id: Int[Axis], buf_mode: Int) -> Int;
    /// Sets the in-position window (> 0).
    ["HMPL 5.3.45", ascii] fn SetPosWindow(axis_id: Int[Axis], pos_window: Double[Length]) -> Int;
    /// Sets how long (ms, > 0) the feedback must stay in the window to be in position.
    ["HMPL 5.3.47", ascii] fn SetPosWindowTime(axis_id: Int[Axis], pos_window_time: Double[Time]) -> Int;

    // HMPL ch. 6: electronic gear.
    /// Links a slave to a master; both must be enabled.
    ["HMPL 6.2", ascii] fn EnableGear(axis_master_id: Int[Axis], axis_slave_id: Int[Axis]) -> Int;
    /// Removes the link (disengaging first).
    ["HMPL 6.3", ascii] fn DisableGear(axis_slave_id: Int[Axis] as Changes) -> Int;
    /// Engages the linked slave at a ratio (negative allowed): it follows the master's travel.
    ["HMPL 6.4", ascii] fn GearIn(axis_master_id: Int[Axis], axis_slave_id: Int[Axis] as Moves, gear_ratio: Double[GearRatio]) -> Int;
    /// Disengages the slave; it comes to rest with its deceleration.
    ["HMPL 6.5", ascii] fn GearOut(axis_slave_id: Int[Axis] as Moves) -> Int;

    // HMPL ch. 7: gantry.
    /// Pairs a right-hand (linear) and a left-hand (yaw) axis; both must be disabled.
    ["HMPL 7.2", ascii] fn EnableGantryPair(rhs_axis_id: Int[Axis], lhs_axis_id: Int[Axis]) -> Int;
    /// Splits the pair of an axis; both must be disabled.
    ["HMPL 7.3", ascii] fn DisableGantryPair(axis_id: Int[Axis]) -> Int;

    // HMPL 8.2: group motion control. Every group command returns 0 or the group's error
    // `0x82IIEEEE` (table 18.1.3.1), also kept as its last error (HMPL 18.5).
    /// Enables the group; every axis in it must be enabled first (0x82II03F2 otherwise).
    ["HMPL 8.2.1", ascii] fn EnableGroup(group_id: Int[Group] as MovesGroup) -> Int;
    /// Disables the group; its axes stay grouped and enabled, its path planning is cleared.
    ["HMPL 8.2.2", ascii] fn DisableGroup(group_id: Int[Group] as MovesGroup) -> Int;
    /// Group Error Stop -> Group Standby, once every cause is gone (axes enabled, no error stop).
    ["HMPL 8.2.3", ascii] fn ResetGroup(group_id: Int[Group] as MovesGroup) -> Int;
    /// Decelerates along the path and clears the group's command buffer.
    ["HMPL 8.2.4", ascii] fn StopGroup(group_id: Int[Group] as MovesGroup) -> Int;
    /// Pauses the group's motion (path velocity to 0), keeping the path for `ResumeGroup`.
    ["HMPL 8.2.5", ascii] fn HaltGroup(group_id: Int[Group] as MovesGroup) -> Int;
    /// Continues a halted group along the same path.
    ["HMPL 8.2.6", ascii] fn ResumeGroup(group_id: Int[Group] as MovesGroup) -> Int;
    /// Jogs the tool in MCS along X, Y, Z, A, B or C (`carte_dir` 0..5) at a signed
    /// velocity (mm/s or deg/s) until `StopGroup` or a jog velocity of 0.
    ["HMPL 8.2.7", ascii] fn JogGroup(group_id: Int[Group] as MovesGroup, carte_dir: Int, jog_vel: Double[GroupJogVelocity]) -> Int;
    /// Jogs one axis of the group (`grp_axis` 0..8, in the order added) at a signed velocity.
    ["HMPL 8.2.8", ascii] fn JogGroupAxis(group_id: Int[Group] as MovesGroup, grp_axis: Int, jog_vel: Double[GroupJogVelocity]) -> Int;
    /// Linear interpolation to (X, Y) in the group's coordinate system.
    ["HMPL 8.2.9", ascii] fn LineAbs2D(group_id: Int[Group] as MovesGroup, end_x: Double[PathCoordinate], end_y: Double[PathCoordinate]) -> Int;
    /// Linear interpolation to (X, Y, Z).
    ["HMPL 8.2.10", ascii] fn LineAbs3D(group_id: Int[Group] as MovesGroup, end_x: Double[PathCoordinate], end_y: Double[PathCoordinate], end_z: Double[PathCoordinate]) -> Int;
    /// Linear interpolation by (dX, dY) from where the queued path ends.
    ["HMPL 8.2.11", ascii] fn LineRel2D(group_id: Int[Group] as MovesGroup, distance_x: Double[PathCoordinate], distance_y: Double[PathCoordinate]) -> Int;
    /// Linear interpolation by (dX, dY, dZ).
    ["HMPL 8.2.12", ascii] fn LineRel3D(group_id: Int[Group] as MovesGroup, distance_x: Double[PathCoordinate], distance_y: Double[PathCoordinate], distance_z: Double[PathCoordinate]) -> Int;
    /// Arc through a border point to an end point (three points; less than a full turn).
    ["HMPL 8.2.13", ascii] fn Arc2D(group_id: Int[Group] as MovesGroup, border_x: Double[PathCoordinate], border_y: Double[PathCoordinate], end_x: Double[PathCoordinate], end_y: Double[PathCoordinate]) -> Int;
    /// Clockwise arc about a center to an end point on the same radius.
    ["HMPL 8.2.14", ascii] fn ArcCW2D(group_id: Int[Group] as MovesGroup, center_x: Double[PathCoordinate], center_y: Double[PathCoordinate], end_x: Double[PathCoordinate], end_y: Double[PathCoordinate]) -> Int;
    /// Counter-clockwise arc about a center to an end point on the same radius.
    ["HMPL 8.2.15", ascii] fn ArcCCW2D(group_id: Int[Group] as MovesGroup, center_x: Double[PathCoordinate], center_y: Double[PathCoordinate], end_x: Double[PathCoordinate], end_y: Double[PathCoordinate]) -> Int;
    /// Arc about a center by `angle` degrees: > 0 counter-clockwise, < 0 clockwise.
    ["HMPL 8.2.16", ascii] fn ArcAngle2D(group_id: Int[Group] as MovesGroup, center_x: Double[PathCoordinate], center_y: Double[PathCoordinate], angle: Double[PathAngle]) -> Int;
    /// Circular motion about a center to an end point; `turns` >= 0 counter-clockwise, < 0
    /// clockwise; total angle θ + (turns-1)·360 for turns >= 1 (0 as 1), θ + turns·360 below.
    ["HMPL 8.2.17", ascii] fn Circle2D(group_id: Int[Group] as MovesGroup, center_x: Double[PathCoordinate], center_y: Double[PathCoordinate], end_x: Double[PathCoordinate], end_y: Double[PathCoordinate], turns: Int) -> Int;

    // HMPL 8.3: group settings.
    /// Appends an axis to the group (X, Y, Z, A, B, C order; at most 9); the group is disabled.
    ["HMPL 8.3.1", ascii] fn AddAxisToGrp(group_id: Int[Group], axis_id: Int) -> Int;
    /// Removes the axis added last; the group is disabled.
    ["HMPL 8.3.2", ascii] fn RemoveAxisFromGrp(group_id: Int[Group]) -> Int;
    /// Disables the group and removes all its axes.
    ["HMPL 8.3.4", ascii] fn UngrpAllAxes(group_id: Int[Group]) -> Int;
    /// Sets the linear (TCP) profile: vel 0..5000 mm/s, acc and dec > 0..50000 mm/s²,
    /// smooth time 0..500 ms. Defaults 100, 5000, 5000, 50.
    ["HMPL 8.3.6", ascii] fn SetGrpMotionProfile(group_id: Int[Group], max_velocity: Double[PathVelocity], max_acceleration: Double[PathAcceleration], max_deceleration: Double[PathDeceleration], smooth_time: Double[PathSmoothTime]) -> Int;
    /// Sets the angular profile: vel 0..7200 deg/s, acc and dec > 0..72000 deg/s², smooth
    /// time 0..500 ms. Defaults 360, 1800, 1800, 50.
    ["HMPL 8.3.7", ascii] fn SetGrpAngMotionProfile(group_id: Int[Group], max_velocity: Double[AngularVelocity], max_acceleration: Double[AngularAcceleration], max_deceleration: Double[AngularDeceleration], smooth_time: Double[AngularSmoothTime]) -> Int;
    /// Sets the kinematics: 1 Cartesian (2 SCARA, 3 wafer, 4 articulated are not available).
    ["HMPL 8.3.9", ascii] fn SetGrpKin(group_id: Int[Group], kin_type: Int) -> Int;
    /// Sets the linear profile velocity, 0..5000 mm/s.
    ["HMPL 8.3.11", ascii] fn SetGrpVel(group_id: Int[Group], vel: Double[PathVelocity]) -> Int;
    /// Sets the linear profile acceleration, > 0..50000 mm/s².
    ["HMPL 8.3.13", ascii] fn SetGrpAcc(group_id: Int[Group], acc: Double[PathAcceleration]) -> Int;
    /// Sets the acceleration from a time (ms > 0): acc = vel / time.
    ["HMPL 8.3.14", ascii] fn SetGrpAccTime(group_id: Int[Group], acc_time: Double[PathAccTime]) -> Int;
    /// Sets the linear profile deceleration, > 0..50000 mm/s².
    ["HMPL 8.3.16", ascii] fn SetGrpDec(group_id: Int[Group], dec: Double[PathDeceleration]) -> Int;
    /// Sets the deceleration from a time (ms > 0): dec = vel / time.
    ["HMPL 8.3.17", ascii] fn SetGrpDecTime(group_id: Int[Group], dec_time: Double[PathDecTime]) -> Int;
    /// Sets the smooth time, 0..500 ms.
    ["HMPL 8.3.19", ascii] fn SetGrpSMTime(group_id: Int[Group], smooth_time: Double[PathSmoothTime]) -> Int;
    /// Selects the coordinate system of later targets: `CS_MCS`, or flags such as
    /// `CS_OFFSET | CS_WCS2 | CS_PCS`.
    ["HMPL 8.3.21", ascii] fn SetGrpCoordSys(group_id: Int[Group], coord_sys: Int) -> Int;
    /// Sets the buffer mode of later commands: BM_BUFF, BM_ABORT, BM_LOW, BM_PREV, BM_NEXT,
    /// BM_HIGH or BM_LOOKAHEAD.
    ["HMPL 8.3.23", ascii] fn SetGrpBufferMode(group_id: Int[Group], buffer_mode: Int) -> Int;
    /// Sets the transition mode of later junctions: TM_NONE, TM_CONST_VEL, TM_CORNER_DIST,
    /// TM_MAX_CORNER_DEV or TM_MAX_CORNER_CURV.
    ["HMPL 8.3.25", ascii] fn SetGrpTransMode(group_id: Int[Group], trans_mode: Int) -> Int;
    /// Sets the transition parameters (table 8.3.26.1): velocity (0, 5000) mm/s, distance
    /// and deviation mm > 0, curvature (0, 1e7) 1/mm; the ones the mode does not use may be 0.
    ["HMPL 8.3.26", ascii] fn SetGrpTransPrm(group_id: Int[Group], trans_vel: Double[TransitionParameter], trans_dis: Double[TransitionParameter], trans_dev: Double[TransitionParameter], trans_curv: Double[TransitionParameter]) -> Int;
    /// Sets the velocity override, 0..100 %, applied along the path under way.
    ["HMPL 8.3.28", ascii] fn SetGrpVelScale(group_id: Int[Group], vel_scale: Double[PathVelScale]) -> Int;
    /// The transform {X, Y, Z mm, A, B, C deg} of `CS_PCS`, `CS_WCSn` or `CS_OFFSET`: `rc, trans_param`.
    ["HMPL 8.3.30"] fn GetGrpCoordTrans(group_id: Int[Group], coord_sys: Int) -> (Int, Doubles);
    /// Sets the transform {X, Y, Z mm, A, B, C deg} (fixed-frame roll-pitch-yaw) of
    /// `CS_PCS`, `CS_WCSn` or `CS_OFFSET`.
    ["HMPL 8.3.31"] fn SetGrpCoordTrans(group_id: Int[Group], coord_sys: Int, trans_param: Doubles[PathCoordinate]) -> Int;
    /// The commanded pose {X, Y, Z, A, B, C} in a coordinate system: `rc, pose_cmd`.
    ["HMPL 8.3.32"] fn GetGrpPoseCmd(group_id: Int[Group], coord_sys: Int) -> (Int, Doubles);
    /// The pose from the axes' feedback in a coordinate system: `rc, pose_fb`.
    ["HMPL 8.3.33"] fn GetGrpPoseFb(group_id: Int[Group], coord_sys: Int) -> (Int, Doubles);
    /// Sets a look-ahead parameter: 0 corner acceleration (default 5000 mm/s²), 1 arc
    /// acceleration (default 100 mm/s²), 2 chord error (default 0: off), mm.
    ["HMPL 8.3.34", ascii] fn SetGrpLookAheadPrm(group_id: Int[Group], prm_id: Int, value: Double[LookAheadParameter]) -> Int;
    /// Sets the command buffer's size to 2^queue_size (0..10; default 512); only when empty.
    ["HMPL 8.3.35", ascii] fn SetGrpQueueSize(group_id: Int[Group], queue_size: Int) -> Int;

    // HMPL 8.5: advanced group motion. `motion_profile` = {vel, acc, dec, smooth_time} as
    // SetGrpMotionProfile; `trans_par` = {trans_vel, trans_dis, trans_dev, trans_curv}
    // (0 or an empty table with TM_NONE).
    /// Linear motion to a 6-D target {X, Y, Z, A, B, C} in `coord_sys`.
    ["HMPL 8.5.1"] fn LineAbs(group_id: Int[Group] as MovesGroup, target_pos: Doubles[PathCoordinate], motion_profile: Doubles[MotionProfile], coord_sys: Int, buff_mode: Int, trans_mode: Int, trans_par: Doubles[TransitionParameter]) -> Int;
    /// Linear motion by a 6-D distance.
    ["HMPL 8.5.2"] fn LineRel(group_id: Int[Group] as MovesGroup, relative_dist: Doubles[PathCoordinate], motion_profile: Doubles[MotionProfile], coord_sys: Int, buff_mode: Int, trans_mode: Int, trans_par: Doubles[TransitionParameter]) -> Int;
    /// 3-D circle about `center_pos` with the rotation of `normal_vector` (right-hand rule),
    /// `turns` as Circle2D, to a 6-D target; a target off the circle's plane makes a helix.
    ["HMPL 8.5.3"] fn CircleAbs(group_id: Int[Group] as MovesGroup, center_pos: Doubles[PathCoordinate], normal_vector: Doubles[PathCoordinate], turns: Int, target_pos: Doubles[PathCoordinate], motion_profile: Doubles[MotionProfile], coord_sys: Int, buff_mode: Int, trans_mode: Int, trans_par: Doubles[TransitionParameter]) -> Int;
    /// As CircleAbs with a target relative to where the queued path ends (the center is absolute).
    ["HMPL 8.5.4"] fn CircleRel(group_id: Int[Group] as MovesGroup, center_pos: Doubles[PathCoordinate], normal_vector: Doubles[PathCoordinate], turns: Int, relative_dist: Doubles[PathCoordinate], motion_profile: Doubles[MotionProfile], coord_sys: Int, buff_mode: Int, trans_mode: Int, trans_par: Doubles[TransitionParameter]) -> Int;

    // HMPL ch. 20: homing.
    /// Runs the drive's homing (needs 0x6060/0x6061 mapped) and returns when it is over:
    /// 0 when homed, else the error (0x83II0424 timeout, 0x83II042E failed, 0x83II00D2 while
    /// compensating).
    ["HMPL 20.2", ascii] fn MoveHome(axis_id: Int[Axis] as Moves) -> Int;
    /// Sets the homing method: 1, 2, 7-14, 17, 18, 23-30, 33, 34, 37 (default 33).
    ["HMPL 20.3", ascii] fn SetHomeMethod(axis_id: Int[Axis], method: Int) -> Int;
    /// Sets the fast homing speed, searching the switch (default 20).
    ["HMPL 20.4", ascii] fn SetHomeSwitchVel(axis_id: Int[Axis], fast_vel: Double[Speed]) -> Int;
    /// Sets the slow homing speed, searching the index (default 5).
    ["HMPL 20.5", ascii] fn SetHomeZeroVel(axis_id: Int[Axis], slow_vel: Double[Speed]) -> Int;
    /// Sets the homing acceleration (default 2000).
    ["HMPL 20.6", ascii] fn SetHomeAcc(axis_id: Int[Axis], acc: Double[Acceleration]) -> Int;
    /// Sets the position the home reads after homing (default 0).
    ["HMPL 20.7", ascii] fn SetHomeOffset(axis_id: Int[Axis], offset: Double[Position]) -> Int;
    /// Sets the homing timeout, ms (default 120000).
    ["HMPL 20.8", ascii] fn SetHomeTimeout(axis_id: Int[Axis], timeout: Int) -> Int;
    /// Sets the homed flag by hand (for homing routines of one's own).
    ["HMPL 20.9", ascii] fn SetHomedStatus(axis_id: Int[Axis], is_homed: Int) -> Int;

    // HMPL ch. 14: dynamic error compensation. The values are `num_pt` entries of the user
    // table from `start_idx` (the first reference axis varies fastest), at most 2048; the
    // position output is reference + compensation, at most 1 mm (0x83II0802). 0 or the
    // axis' error: 0x83II012C a table no axis can have, 0x83II00D2 while active.
    /// Enables the compensation set up for the axis (its values are read from the user
    /// table now); only while the axis is disabled (0x83II006E), after a setup (0x83II0190),
    /// with the axis and its reference axes homed (0x83II0064). It applies once enabled.
    ["HMPL 14.2", ascii] fn EnableComp(axis_id: Int[Axis]) -> Int;
    /// Disables the compensation and clears its setup; only while the axis is disabled
    /// (0x83II006E). The reference becomes the position the axis stands at.
    ["HMPL 14.3", ascii] fn DisableComp(axis_id: Int[Axis]) -> Int;
    /// A 1-D table: `num_pt` values (2 or more) for reference positions
    /// `base_val + k * interval` of axis `ref_axis_id`.
    ["HMPL 14.4", ascii] fn SetupComp(axis_id: Int[Axis], start_idx: Int, base_val: Double[CompTable], interval: Double[CompTable], num_pt: Int, ref_axis_id: Int) -> Int;
    /// A 2-D table: `base_val`, `interval`, `num_pt` and `ref_axis_id` are tables of 2, one
    /// entry per dimension; as many values as the product of `num_pt`.
    ["HMPL 14.5"] fn SetupComp2D(axis_id: Int[Axis], start_idx: Int, base_val: Doubles[CompTable], interval: Doubles[CompTable], num_pt: Doubles[CompTable], ref_axis_id: Doubles[CompTable]) -> Int;
    /// A 3-D table: as `SetupComp2D` with tables of 3; linear only.
    ["HMPL 14.6"] fn SetupComp3D(axis_id: Int[Axis], start_idx: Int, base_val: Doubles[CompTable], interval: Doubles[CompTable], num_pt: Doubles[CompTable], ref_axis_id: Doubles[CompTable]) -> Int;
    /// 0: linear between the points (the default), 1: natural cubic spline (1-D and 2-D);
    /// not while active.
    ["HMPL 14.8", ascii] fn SetCompAlgType(axis_id: Int[Axis], alg_type: Int) -> Int;

    // HMPL ch. 18: errors.
    /// Clears the axis' last error.
    ["HMPL 18.4", ascii] fn ClearAxisLastErr(axis_id: Int[Axis]) -> Int;
    /// Clears a group's last error.
    ["HMPL 18.6", ascii] fn ClearGrpLastErr(group_id: Int as Group) -> Int;

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
    /// Simulator only: the electrical level of controller input `gpi_idx` (1..8), before
    /// inversion, as a switch wired to it would set it. Returns 0 or -1.
    ["luamotion sim", ascii] fn SimSetGPI(gpi_idx: Int, on_off: Int) -> Int;
    /// Simulator only: the switch on input `gpi_idx` (1..) of a digital I/O terminal
    /// (`[[slaves]] device = "digital_io"`), as wired to it. Returns 0, or -1 for no such
    /// terminal or input (a drive's inputs are not simulated).
    ["luamotion sim", ascii] fn SimSetSlvGPI(slv_slot_id: Int, gpi_idx: Int, on_off: Int) -> Int;

    // HMPL ch. 2: system.
    /// Disables every axis and clears its path planning.
    ["HMPL 2.7", ascii] fn DisableAll() -> Int;
    /// Stops every axis with its kill deceleration; they stay enabled; the plans are cleared.
    ["HMPL 2.8", ascii] fn StopAll() -> Int;
    /// Emergency stop: stops every task (the caller too: the call never returns) and
    /// disables every axis. Motion commands then fail with 0x0064 until the axis is enabled again.
    ["HMPL 2.9", ascii] fn EStop();
    /// Rescans the EtherCAT segment: every slave back to Pre-Op, configured and brought to
    /// Op again, the slaves' table renewed. 0, or 0x138C while an axis or a group is enabled
    /// or the controller is not in a state that allows it (docs/decisions.md, "System").
    ["HMPL 2.16", ascii] fn ScanNetwork() -> Int;

    // HMPL ch. 9: the controller's digital I/O (pins 1..8); 0 or -1.
    /// Sets output `gpo_idx` on (1) or off (0).
    ["HMPL 9.2.1", ascii] fn SetGPO(gpo_idx: Int, on_off: Int) -> Int;
    /// Toggles output `gpo_idx`.
    ["HMPL 9.2.2", ascii] fn ToggleGPO(gpo_idx: Int) -> Int;
    /// Sets all outputs from a bitmask (bit 0 is pin 1).
    ["HMPL 9.2.3", ascii] fn SetAllGPO(all_gpo_state: Int) -> Int;
    /// Inverts input `gpi_idx` (1) or not (0).
    ["HMPL 9.2.4", ascii] fn SetGPIInvert(gpi_idx: Int, invert: Int) -> Int;
    /// Inverts output `gpo_idx` (1) or not (0).
    ["HMPL 9.2.5", ascii] fn SetGPOInvert(gpo_idx: Int, invert: Int) -> Int;

    // HMPL 9.3: a slave's digital outputs (`slv_id | HMPL_SLOT_n`, channels 1..), written
    // into its process data (a terminal's 0x7000:01, a drive's 0x60FE:01 when mapped); 0 or -1.
    /// Sets output `gpo_idx` of a slave on (1) or off (0).
    ["HMPL 9.3.1", ascii] fn SetSlvGPO(slv_slot_id: Int, gpo_idx: Int, on_off: Int) -> Int;
    /// Toggles output `gpo_idx` of a slave.
    ["HMPL 9.3.2", ascii] fn ToggleSlvGPO(slv_slot_id: Int, gpo_idx: Int) -> Int;
    /// Sets all outputs of a slave from a bitmask (bit 0 is output 1).
    ["HMPL 9.3.3", ascii] fn SetSlvAllGPO(slv_slot_id: Int, all_gpo_state: Int) -> Int;

    // HMPL ch. 13: touch probes, through the drive's 0x60B8 in the second RxPDO (0x1601).
    // 0x83II0258 when the probe's objects are not in the process data (probe 2 on a drive
    // without it), 0x83II012C for an argument the drive cannot do.
    /// Arms touch probe 1 with the function `SetTouchProbe1Func` set (by default the
    /// index, single, rising edge); a single-trigger probe latches again once re-enabled.
    ["HMPL 13.2", ascii] fn EnableTouchProbe1(axis_id: Int[Axis]) -> Int;
    /// Arms touch probe 2 (as `EnableTouchProbe1`).
    ["HMPL 13.3", ascii] fn EnableTouchProbe2(axis_id: Int[Axis]) -> Int;
    /// Switches touch probe 1 off; its latched state is cleared.
    ["HMPL 13.4", ascii] fn DisableTouchProbe1(axis_id: Int[Axis]) -> Int;
    /// Switches touch probe 2 off.
    ["HMPL 13.5", ascii] fn DisableTouchProbe2(axis_id: Int[Axis]) -> Int;
    /// Touch probe 1's signal (`tp_input` 0 the drive's probe input, 1 the encoder index),
    /// trigger (`cont_trigger` 0 first edge only, 1 every edge) and edge (`detect_edge` 0
    /// rising, 1 falling); applied at once, re-arming an enabled probe.
    ["HMPL 13.12", ascii] fn SetTouchProbe1Func(axis_id: Int[Axis], tp_input: Int, cont_trigger: Int, detect_edge: Int) -> Int;
    /// Touch probe 2's function (as `SetTouchProbe1Func`).
    ["HMPL 13.13", ascii] fn SetTouchProbe2Func(axis_id: Int[Axis], tp_input: Int, cont_trigger: Int, detect_edge: Int) -> Int;
    /// Chooses the input whose rising edge is the E-stop (default 8; 0: none).
    ["HMPL 9.2.6", ascii] fn BindEMO(gpi_idx: Int) -> Int;

    // HMPL ch. 15: filters on the reference, after the smoothing; VSF and InShape never
    // together on one axis; every one refused while the axis or group moves (0x83II0082,
    // 0x82II0046). Axis InShape leaves group motion alone: the group has its own.
    /// Turns the axis' vibration suppression filter (a notch at `SetAxisVsf`'s frequency) on;
    /// 0x83II00C8 while input shaping is on.
    ["HMPL 15.2", ascii] fn EnableAxisVsf(axis_id: Int[Axis]) -> Int;
    /// Turns the axis' VSF off.
    ["HMPL 15.3", ascii] fn DisableAxisVsf(axis_id: Int[Axis]) -> Int;
    /// Sets the VSF's frequency (0.1..200 Hz, below 0.45 of the cycle rate) and damping ratio
    /// (0.7..1.5, 1.0 recommended: the notch's width).
    ["HMPL 15.4", ascii] fn SetAxisVsf(axis_id: Int[Axis], frequency: Double[VsfFrequency], damping_ratio: Double[VsfDamping]) -> Int;
    /// Turns the axis' input shaper on; 0x83II0064 while the VSF is on.
    ["HMPL 15.5", ascii] fn EnableAxisInShape(axis_id: Int[Axis]) -> Int;
    /// Turns the axis' input shaper off.
    ["HMPL 15.6", ascii] fn DisableAxisInShape(axis_id: Int[Axis]) -> Int;
    /// Sets the axis' input shaper: the load's frequency (1.5..300 Hz, default 5.5), damping
    /// ratio (0..0.3, default 0.03) and type (1 SHAPER_NORMAL: ZV, 0 SHAPER_ROBUST: ZVD).
    ["HMPL 15.7", ascii] fn SetAxisInShape(axis_id: Int[Axis], frequency: Double[ShaperFrequency], damping_ratio: Double[ShaperDamping], shaper_type: Int) -> Int;
    /// Turns the group's input shaper on (every coordinate of its path).
    ["HMPL 15.8", ascii] fn EnableGrpInShape(group_id: Int[Group]) -> Int;
    /// Turns the group's input shaper off.
    ["HMPL 15.9", ascii] fn DisableGrpInShape(group_id: Int[Group]) -> Int;
    /// Sets the group's input shaper: frequency 3.0..300 Hz, damping 0..0.3, type as
    /// SetAxisInShape (0x82II005A for another type).
    ["HMPL 15.10", ascii] fn SetGrpInShape(group_id: Int[Group], frequency: Double[GroupShaperFrequency], damping_ratio: Double[GroupShaperDamping], shaper_type: Int) -> Int;

    // HMPL 10.2, 10.4: a slave's analog channels (`slv_id | HMPL_SLOT_n`, channels 1..), an
    // analog terminal's 0x6401:nn inputs and 0x6411:nn outputs in its process data. 0, or
    // 0x138F no such slave, channel or object in the process data, value out of range;
    // 0x1388 no such conversion type or variable; 0x138C the channel has no conversion
    // type, or the output is bound (docs/decisions.md, "Slave analog I/O").
    /// Sets an analog input's conversion type (`HMPL_DAC_*` of table 10.1.1, optionally
    /// `| HMPL_DAC_SIGNED`).
    ["HMPL 10.2.1", ascii] fn SetSlvAIType(slv_slot_id: Int, ai_idx: Int, range_type: Int) -> Int;
    /// Sets an analog output's conversion type; not `HMPL_DAC_NONE` while it is bound.
    ["HMPL 10.2.2", ascii] fn SetSlvAOType(slv_slot_id: Int, ao_idx: Int, range_type: Int) -> Int;
    /// Writes an analog output's 16-bit word: 0..65535, or -32768..32767 as two's complement.
    ["HMPL 10.2.3", ascii] fn SetSlvAORaw(slv_slot_id: Int, ao_idx: Int, ao_raw_val: Int) -> Int;
    /// Writes an analog output in its conversion type's units (within its range; the top
    /// value gives the top word).
    ["HMPL 10.2.4", ascii] fn SetSlvAO(slv_slot_id: Int, ao_idx: Int, ao_val: Double[Finite]) -> Int;
    /// Chooses the variable an analog output follows: `HMPL_AXIS_n | HMPL_<VAR>` (REF_POS,
    /// REF_VEL, REF_ACC, POS_FB, VEL_FB, ACC_FB, CUR_FB); needs a conversion type.
    ["HMPL 10.4.1", ascii] fn SetSlvAOMonitor(slv_slot_id: Int, ao_idx: Int, var_id: Int) -> Int;
    /// Binds (1) or frees (0) an analog output: every cycle it is var * scale + offset in its
    /// type's units, saturated at the range's ends. Binding needs `SetSlvAOMonitor` first.
    ["HMPL 10.4.2", ascii] fn SetSlvAOParam(slv_slot_id: Int, ao_idx: Int, ao_en_bind: Int, ao_scale: Double[Finite], ao_offset: Double[Finite]) -> Int;
    /// Simulator only: the word an analog terminal's converter reads on input `ai_idx`
    /// (0..65535, or -32768..32767), as a signal wired to it would make it. 0 or 0x138F.
    ["luamotion sim", ascii] fn SimSetSlvAIRaw(slv_slot_id: Int, ai_idx: Int, ai_raw_val: Int) -> Int;

    // HMPL ch. 16: task control.
    /// Starts a task's program in its own process; returns once it runs. 0x0107 no such
    /// task id, 0x0108 already running, 0x010A no program configured.
    ["HMPL 16.2", ascii] fn StartTask(task_id: Int) -> Int;
    /// Starts a task at a function of its program: the program's top level runs first (it
    /// should only declare), then `func_name()`. 0x0109 when the program has no such function.
    ["HMPL 16.3", ascii] fn StartTaskFunc(task_id: Int, func_name: Str) -> Int;
    /// Stops a task: its motion reacts as its fault reaction says, its mutexes are released,
    /// its process ends. 0x010B when it is not running.
    ["HMPL 16.4", ascii] fn StopTask(task_id: Int) -> Int;
    /// Stops every task, the caller too: the call never returns.
    ["HMPL 16.5", ascii] fn StopAllTask();

    // Fatek FBs-PLC FUN147 (MHSPO): the step table, run by the core every cycle on the
    // group interpolator (docs/fun147.md).
    /// Declares the FUN147 box of group `gp` (Gp, 0 or 1): its step table at `sr` (SR), its
    /// working registers WR+0..WR+8 at `wr` ("R2000", "D0": R0-R3839, R5000-R8071,
    /// D0-D3999), the relays it reads every cycle (EN, PAU, ABT) and writes (ACT, ERR, DN):
    /// "X0"-"X255", "Y0"-"Y255", "M0"-"M2001", "S0"-"S999". Psi is axis i, one pulse 0.001
    /// axis unit; box Gp moves through group 14 + Gp. Declaring a group's box again
    /// replaces it (stopped first). 0, or 0x138F for an operand that does not exist.
    ["Fatek FUN147"] fn MHSPO(gp: Int, sr: Str, wr: Str, en: Str, pau: Str, abt: Str, act: Str, err: Str, dn: Str) -> Int;
    /// Stops the box of group `gp` at once, frees its axes and removes it. 0, or 0x138F
    /// for a `gp` other than 0 and 1.
    ["Fatek FUN147"] fn MHSPOFree(gp: Int) -> Int;

    // HMPL ch. 12: the position trigger (PT) of an axis whose drive has one (`[axes.pt]` in
    // the machine file; 0x1451 otherwise). Pulses on the axis' PT output where its feedback
    // crosses each point (docs/decisions.md, "Position trigger"). Settings take effect at
    // the next `EnablePT`; a bad argument is 0x83II012C.
    /// Starts a pass over the points set last (equidistant or the position array); the axis
    /// must be homed (0x83II0064). The pass ends by itself after its last point.
    ["HMPL 12.2", ascii] fn EnablePT(axis_id: Int[Axis]) -> Int;
    /// Ends the pass under way; the points not reached give no pulse.
    ["HMPL 12.3", ascii] fn DisablePT(axis_id: Int[Axis]) -> Int;
    /// The first point of equidistant PT; a start above the end triggers on negative motion.
    ["HMPL 12.5", ascii] fn SetPT_StartPos(axis_id: Int[Axis], start_pos: Double[Position]) -> Int;
    /// The last point of equidistant PT: no pulse beyond it.
    ["HMPL 12.6", ascii] fn SetPT_EndPos(axis_id: Int[Axis], end_pos: Double[Position]) -> Int;
    /// The spacing of equidistant PT (> 0). The axis' speed must stay below interval x 16 kHz
    /// (HMPL 12.1.1): a point reached in the same drive sample as the one before gives no
    /// pulse and is counted as missed.
    ["HMPL 12.7", ascii] fn SetPT_Interval(axis_id: Int[Axis], interval: Double[Length]) -> Int;
    /// The pulse width, 20..80000 ns in steps of 20 (E1 drive). A controller GPO shows each
    /// pulse for at least one cycle.
    ["HMPL 12.8", ascii] fn SetPT_PulseWidth(axis_id: Int[Axis], width_ns: Int) -> Int;
    /// Point `index` (0..255) of the position array, and chooses array PT.
    ["HMPL 12.9"] fn SetPT_PosArray(axis_id: Int[Axis], index: Int, trigger_pos: Double[Position]) -> Int;
    /// State word `index` (0..7): bit k of word k/32 is point k's output, 1 a pulse, 0 none
    /// (all 1 until set).
    ["HMPL 12.10", ascii] fn SetPT_StateArray(axis_id: Int[Axis], index: Int, state: Int) -> Int;
    /// The array index (0..255) the pass starts at; above the end index, it runs backwards
    /// and triggers on negative motion. Chooses array PT.
    ["HMPL 12.11", ascii] fn SetPT_StartIndex(axis_id: Int[Axis], index: Int) -> Int;
    /// The array index (0..255) the pass ends at. Chooses array PT.
    ["HMPL 12.12", ascii] fn SetPT_EndIndex(axis_id: Int[Axis], index: Int) -> Int;
    /// Pulse `n` (from 0) of the last pass: its position and the controller time (ms,
    /// interpolated within the cycle) its point was crossed; the first 256 pulses are kept.
    /// 0x83II012C for a pulse that was not given.
    ["luamotion sim"] fn GetPTPulse(axis_id: Int[Axis], n: Int) -> (Int, Double, Double);
}

declare_functions! {
    Query, QUERIES => QueryCall;

    // HMPL 5.3: axis settings and variables (mm or deg, s, ms).
    /// The profile velocity.
    ["HMPL 5.3.1", ascii] fn GetVel(axis_id: Int) -> Double;
    /// The profile acceleration.
    ["HMPL 5.3.3", ascii] fn GetAcc(axis_id: Int) -> Double;
    /// The profile deceleration.
    ["HMPL 5.3.6", ascii] fn GetDec(axis_id: Int) -> Double;
    /// The kill deceleration.
    ["HMPL 5.3.9", ascii] fn GetKillDec(axis_id: Int) -> Double;
    /// The software right limit.
    ["HMPL 5.3.11", ascii] fn GetSWRL(axis_id: Int) -> Double;
    /// The software left limit.
    ["HMPL 5.3.13", ascii] fn GetSWLL(axis_id: Int) -> Double;
    /// The smooth time, ms.
    ["HMPL 5.3.15", ascii] fn GetSMTime(axis_id: Int) -> Double;
    /// How long the last move took, ms.
    ["HMPL 5.3.17", ascii] fn GetMoveTime(axis_id: Int) -> Double;
    /// How long the last move took from its end to in position, ms.
    ["HMPL 5.3.18", ascii] fn GetSettlingTime(axis_id: Int) -> Double;
    /// Position feedback.
    ["HMPL 5.3.20", ascii] fn GetPosFb(axis_id: Int) -> Double;
    /// Position feedback with the compensation in it, as the drive reports it; `GetPosFb`
    /// is the feedback without it, in the reference's coordinates.
    ["HMPL 5.3.21", ascii] fn GetPosFbComp(axis_id: Int) -> Double;
    /// The offset `SetPos` put between the axis and the drive.
    ["HMPL 5.3.22", ascii] fn GetPosOffset(axis_id: Int) -> Double;
    /// Position error: output minus feedback.
    ["HMPL 5.3.23", ascii] fn GetPosErr(axis_id: Int) -> Double;
    /// Velocity feedback.
    ["HMPL 5.3.24", ascii] fn GetVelFb(axis_id: Int) -> Double;
    /// Velocity error.
    ["HMPL 5.3.25", ascii] fn GetVelErr(axis_id: Int) -> Double;
    /// Current feedback, A (needs 0x6077 mapped).
    ["HMPL 5.3.26", ascii] fn GetCurrFb(axis_id: Int) -> Double;
    /// Reference position: the profile generator's output.
    ["HMPL 5.3.27", ascii] fn GetRefPos(axis_id: Int) -> Double;
    /// Reference velocity.
    ["HMPL 5.3.28", ascii] fn GetRefVel(axis_id: Int) -> Double;
    /// Reference acceleration.
    ["HMPL 5.3.29", ascii] fn GetRefAcc(axis_id: Int) -> Double;
    /// Position output: reference plus compensation.
    ["HMPL 5.3.30", ascii] fn GetPosOut(axis_id: Int) -> Double;
    /// Velocity output.
    ["HMPL 5.3.31", ascii] fn GetVelOut(axis_id: Int) -> Double;
    /// Acceleration output.
    ["HMPL 5.3.32", ascii] fn GetAccOut(axis_id: Int) -> Double;
    /// The number of axes.
    ["HMPL 5.3.36", ascii] fn GetAxisNum() -> Int;
    /// The velocity override, %.
    ["HMPL 5.3.38", ascii] fn GetVelScale(axis_id: Int) -> Double;
    /// Whole turns counted in rollover mode.
    ["HMPL 5.3.40", ascii] fn GetRolloverTurns(axis_id: Int) -> Int;
    /// The buffer mode, 0 or 1.
    ["HMPL 5.3.43", ascii] fn GetBufferMode(axis_id: Int) -> Int;
    /// Moves waiting in the queue.
    ["HMPL 5.3.44", ascii] fn GetCmdNum(axis_id: Int) -> Int;
    /// The in-position window.
    ["HMPL 5.3.46", ascii] fn GetPosWindow(axis_id: Int) -> Double;
    /// The in-position time, ms.
    ["HMPL 5.3.48", ascii] fn GetPosWindowTime(axis_id: Int) -> Double;

    // HMPL 5.4: axis status.
    /// True when the axis is enabled (drive in Operation enabled).
    ["HMPL 5.4.1", ascii] fn IsEnabled(axis_id: Int) -> Bool;
    /// True while the profile generator still emits new positions.
    ["HMPL 5.4.2", ascii] fn IsMoving(axis_id: Int) -> Bool;
    /// True when the feedback has stayed within the position window for the window time.
    ["HMPL 5.4.3", ascii] fn IsInPos(axis_id: Int) -> Bool;
    /// True in ErrorStop.
    ["HMPL 5.4.4", ascii] fn IsErrorStop(axis_id: Int) -> Bool;
    /// True for an axis of a gantry pair.
    ["HMPL 5.4.5", ascii] fn IsGantry(axis_id: Int) -> Bool;
    /// True for an axis in a group.
    ["HMPL 5.4.6", ascii] fn IsGrouped(axis_id: Int) -> Bool;
    /// True when the axis follows a master (gear slave or group).
    ["HMPL 5.4.7", ascii] fn IsSync(axis_id: Int) -> Bool;
    /// True while the hardware left (negative) limit is active (0x60FD bit 0).
    ["HMPL 5.4.8", ascii] fn IsHWLL(axis_id: Int) -> Bool;
    /// True while the hardware right (positive) limit is active (0x60FD bit 1).
    ["HMPL 5.4.9", ascii] fn IsHWRL(axis_id: Int) -> Bool;
    /// True once the software left limit stopped the axis.
    ["HMPL 5.4.10", ascii] fn IsSWLL(axis_id: Int) -> Bool;
    /// True once the software right limit stopped the axis.
    ["HMPL 5.4.11", ascii] fn IsSWRL(axis_id: Int) -> Bool;
    /// True when the drive reports a fault.
    ["HMPL 5.4.12", ascii] fn IsDriveErr(axis_id: Int) -> Bool;
    /// True once the position error exceeded its limit.
    ["HMPL 5.4.13", ascii] fn IsPosErr(axis_id: Int) -> Bool;
    /// True when error compensation is active on the axis.
    ["HMPL 5.4.14", ascii] fn IsCompActive(axis_id: Int) -> Bool;
    /// True while the axis accelerates.
    ["HMPL 5.4.15", ascii] fn IsAcc(axis_id: Int) -> Bool;

    // HMPL ch. 6, 7, 20, 18.
    /// The engaged gear ratio (0 when not engaged).
    ["HMPL 6.6", ascii] fn GetGearRatio(axis_slave_id: Int) -> Double;
    /// True when the slave is engaged.
    ["HMPL 6.7", ascii] fn IsInGear(axis_id: Int) -> Bool;
    /// True when the axis is a gear master.
    ["HMPL 6.8", ascii] fn IsGearMaster(axis_id: Int) -> Bool;
    /// True when the axis is a gear slave.
    ["HMPL 6.9", ascii] fn IsGearSlave(axis_id: Int) -> Bool;
    /// The gantry pair's id, -1 when not in a pair.
    ["HMPL 7.4", ascii] fn GetGantryPairID(axis_id: Int) -> Int;
    /// True when the two axes form a pair.
    ["HMPL 7.5", ascii] fn IsGantryPair(axis_id_1: Int, axis_id_2: Int) -> Bool;
    /// True once homing completed (or `SetHomedStatus(a, 1)`).
    ["HMPL 20.10", ascii] fn IsHomed(axis_id: Int) -> Bool;
    /// True while homing runs.
    ["HMPL 20.11", ascii] fn IsHoming(axis_id: Int) -> Bool;
    /// True while the home switch is active (0x60FD bit 2).
    ["HMPL 20.12", ascii] fn IsHomeSwitch(axis_id: Int) -> Bool;
    /// The last system error code (0x0000EEEE; 0: none).
    ["HMPL 18.2", ascii] fn GetSystemLastErr() -> Int;
    /// The axis' last error as a 32-bit code `0x83IIEEEE` (0: none).
    ["HMPL 18.3", ascii] fn GetAxisLastErr(axis_id: Int) -> Int;
    /// A group's last error `0x82IIEEEE` (0: none).
    ["HMPL 18.5", ascii] fn GetGrpLastErr(group_id: Int as Group) -> Int;
    /// The drive's own error code (0x603F).
    ["HMPL 18.7", ascii] fn GetDriveErr(axis_id: Int) -> Int;

    // HMPL ch. 14: dynamic error compensation.
    /// The compensation added to the axis' reference this cycle (0 when none).
    ["HMPL 14.7", ascii] fn GetCompPos(axis_id: Int) -> Double;

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

    /// Controller input `gpi_idx` (1..8) after inversion: 1 on, 0 off, -1 no such input.
    ["HMPL 9.4.1", ascii] fn GetGPI(gpi_idx: Int) -> Int;
    /// Controller output `gpo_idx`: 1 on, 0 off, -1 no such output.
    ["HMPL 9.4.2", ascii] fn GetGPO(gpo_idx: Int) -> Int;
    /// All inputs as a bitmask (inputs 1 and 4 on: 9).
    ["HMPL 9.4.3", ascii] fn GetAllGPI() -> Int;
    /// All outputs as a bitmask (outputs 2 and 3 on: 6).
    ["HMPL 9.4.4", ascii] fn GetAllGPO() -> Int;
    /// The inverted inputs as a bitmask.
    ["HMPL 9.4.5", ascii] fn GetAllGPIInvertSt() -> Int;
    /// The inverted outputs as a bitmask.
    ["HMPL 9.4.6", ascii] fn GetAllGPOInvertSt() -> Int;

    // HMPL 9.5: a slave's digital I/O read from its process data (a terminal's 0x6000:01
    // and 0x7000:01, a drive's 0x60FD and 0x60FE:01 when mapped); -1 for no such slave,
    // channel, or object in the process data.
    /// Input `gpi_idx` of a slave: 1 on, 0 off.
    ["HMPL 9.5.1", ascii] fn GetSlvGPI(slv_slot_id: Int, gpi_idx: Int) -> Int;
    /// Output `gpo_idx` of a slave as the master last sent it: 1 on, 0 off.
    ["HMPL 9.5.2", ascii] fn GetSlvGPO(slv_slot_id: Int, gpo_idx: Int) -> Int;
    /// All inputs of a slave as a bitmask (inputs 1 and 4 on: 9).
    ["HMPL 9.5.3", ascii] fn GetSlvAllGPI(slv_slot_id: Int) -> Int;
    /// All outputs of a slave as a bitmask (outputs 2 and 3 on: 6).
    ["HMPL 9.5.4", ascii] fn GetSlvAllGPO(slv_slot_id: Int) -> Int;
    /// The inputs from `start_idx` on: bit k is input start_idx + k (start 8, inputs 8 and 11 on: 9).
    ["HMPL 9.5.5", ascii] fn GetSlvAllGPIByStartIdx(slv_slot_id: Int, start_idx: Int) -> Int;
    /// The outputs from `start_idx` on: bit k is output start_idx + k (start 8, outputs 9 and 10 on: 6).
    ["HMPL 9.5.6", ascii] fn GetSlvAllGPOByStartIdx(slv_slot_id: Int, start_idx: Int) -> Int;

    // HMPL 10.3, 10.4: a slave's analog channels, from its process data and the settings
    // the controller keeps; an error (0x138F, or 0x138C without a conversion type) as the
    // setters' (docs/decisions.md, "Slave analog I/O").
    /// An analog input's conversion type (`HMPL_DAC_NONE` until set).
    ["HMPL 10.3.1", ascii] fn GetSlvAIType(slv_slot_id: Int, ai_idx: Int) -> Int;
    /// An analog output's conversion type.
    ["HMPL 10.3.2", ascii] fn GetSlvAOType(slv_slot_id: Int, ao_idx: Int) -> Int;
    /// An analog input's word: 0..65535, or signed with `HMPL_DAC_SIGNED`.
    ["HMPL 10.3.3", ascii] fn GetSlvAIRaw(slv_slot_id: Int, ai_idx: Int) -> Int;
    /// An analog input in its conversion type's units.
    ["HMPL 10.3.4", ascii] fn GetSlvAI(slv_slot_id: Int, ai_idx: Int) -> Double;
    /// An analog output's word as the master last sent it: 0..65535, or signed.
    ["HMPL 10.3.5", ascii] fn GetSlvAORaw(slv_slot_id: Int, ao_idx: Int) -> Int;
    /// An analog output in its conversion type's units.
    ["HMPL 10.3.6", ascii] fn GetSlvAO(slv_slot_id: Int, ao_idx: Int) -> Double;
    /// The scale of an analog output's binding (1 until set).
    ["HMPL 10.4.3", ascii] fn GetSlvAOScale(slv_slot_id: Int, ao_idx: Int) -> Double;
    /// The offset of an analog output's binding (0 until set).
    ["HMPL 10.4.4", ascii] fn GetSlvAOOffset(slv_slot_id: Int, ao_idx: Int) -> Double;
    /// 1 when an analog output follows a controller variable, else 0.
    ["HMPL 10.4.5", ascii] fn IsSlvAOBound(slv_slot_id: Int, ao_idx: Int) -> Int;

    // HMPL ch. 13: touch probes, read from the drive's 0x60B9 and 0x60BA..0x60BD in the
    // second TxPDO (0x1A01).
    /// 1 while touch probe 1 is enabled.
    ["HMPL 13.6", ascii] fn IsTouchProbe1Enabled(axis_id: Int) -> Bool;
    /// 1 while touch probe 2 is enabled.
    ["HMPL 13.7", ascii] fn IsTouchProbe2Enabled(axis_id: Int) -> Bool;
    /// 1 once touch probe 1 latched its edge since it was enabled (or its function set).
    ["HMPL 13.8", ascii] fn IsTouchProbe1Triggered(axis_id: Int) -> Bool;
    /// 1 once touch probe 2 latched its edge.
    ["HMPL 13.9", ascii] fn IsTouchProbe2Triggered(axis_id: Int) -> Bool;
    /// `rc, pos`: the position (mm or deg, in the axis' coordinates as the feedback) touch
    /// probe 1 latched on its edge, the last one in continuous mode; 0 before any.
    ["HMPL 13.10"] fn GetTouchProbe1Pos(axis_id: Int) -> (Int, Double);
    /// `rc, pos` of touch probe 2.
    ["HMPL 13.11"] fn GetTouchProbe2Pos(axis_id: Int) -> (Int, Double);

    // HMPL 8.3 and 8.4: group settings and status, read from the snapshot.
    /// The group of an axis, -1 when it is in none.
    ["HMPL 8.3.5", ascii] fn GetGroupID(axis_id: Int) -> Int;
    /// The kinematics id (1 Cartesian).
    ["HMPL 8.3.8", ascii] fn GetGrpKin(group_id: Int) -> Int;
    /// The linear profile velocity, mm/s.
    ["HMPL 8.3.10", ascii] fn GetGrpVel(group_id: Int) -> Double;
    /// The linear profile acceleration, mm/s².
    ["HMPL 8.3.12", ascii] fn GetGrpAcc(group_id: Int) -> Double;
    /// The linear profile deceleration, mm/s².
    ["HMPL 8.3.15", ascii] fn GetGrpDec(group_id: Int) -> Double;
    /// The smooth time, ms.
    ["HMPL 8.3.18", ascii] fn GetGrpSMTime(group_id: Int) -> Double;
    /// The coordinate system flags of later targets.
    ["HMPL 8.3.20", ascii] fn GetGrpCoordSys(group_id: Int) -> Int;
    /// The buffer mode of later commands.
    ["HMPL 8.3.22", ascii] fn GetGrpBufferMode(group_id: Int) -> Int;
    /// The transition mode of later junctions.
    ["HMPL 8.3.24", ascii] fn GetGrpTransMode(group_id: Int) -> Int;
    /// Commands in the group's buffer, the one under way included.
    ["HMPL 8.3.27", ascii] fn GetGrpCmdNum(group_id: Int) -> Int;
    /// The velocity override, 0..100 %.
    ["HMPL 8.3.29", ascii] fn GetGrpVelScale(group_id: Int) -> Double;
    /// True while the group is enabled.
    ["HMPL 8.4.1", ascii] fn IsGrpEnabled(group_id: Int) -> Bool;
    /// True while the group's path generator still outputs positions.
    ["HMPL 8.4.2", ascii] fn IsGrpMoving(group_id: Int) -> Bool;
    /// True when the group stands still and every axis in it is in position.
    ["HMPL 8.4.3", ascii] fn IsGrpInPos(group_id: Int) -> Bool;
    /// True in Group Error Stop.
    ["HMPL 8.4.4", ascii] fn IsGrpErrorStop(group_id: Int) -> Bool;

    /// True unless the task is starting or running.
    ["HMPL 16.6", ascii] fn IsTaskStop(task_id: Int) -> Bool;

    // HMPL ch. 12: the position trigger.
    /// True while a PT pass runs (enabled and points left).
    ["HMPL 12.4", ascii] fn IsPTEnabled(axis_id: Int) -> Bool;
    /// Pulses given in the axis' last PT pass.
    ["luamotion sim"] fn GetPTPulseNum(axis_id: Int) -> Int;
    /// Points of the last pass reached in the same drive sample as the pulse before (the
    /// axis faster than interval x 16 kHz, HMPL 12.1.1): no pulse was given for them.
    ["luamotion sim"] fn GetPTMissedNum(axis_id: Int) -> Int;
}

declare_functions! {
    Local, LOCALS => LocalCall<'a, V>;

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
    /// DRL: word `address` of the Modbus user areas, 0..65535: DV 0x0000..0x2FFF (volatile)
    /// or DH 0x8000..0xAFFF (kept across restarts). A Lua error outside them.
    ["DXMC A.1"] fn ReadModbusWord(address: Int) -> Int;
    /// DRL: writes word `address` of DV or DH; the Modbus clients read it at once. 0, or
    /// 0x138F for an address outside DV and DH or a value outside 0..65535.
    ["DXMC A.1"] fn WriteModbusWord(address: Int, value: Int) -> Int;

    /// Sends event `evt_id` (0..65535) to the tools following the event stream. Blocks
    /// while the task sends faster than 1000 per second on average. Returns 0.
    ["HMPL 2.19", ascii] fn SendEvent(evt_id: Int) -> Int;
    /// Sends a formatted message (as `Print`, at most 128 characters; longer ones are
    /// refused with 0x138D) to the event stream; throttled like `SendEvent`.
    ["HMPL 2.20"] fn SendMsgEvent(format: Str, args: Rest) -> Int;
    /// Gives the processor to other programs for a moment.
    ["HMPL 2.21", ascii] fn RunScheduler();
    /// Takes mutex `mutex_id` (0..7), waiting while another task holds it. Taking it twice
    /// stops the task with 0x13EC. A task that stops releases its mutexes.
    ["HMPL 2.22"] fn MutexLock(mutex_id: Int);
    /// Releases mutex `mutex_id` if this task holds it; otherwise does nothing.
    ["HMPL 2.23"] fn MutexUnlock(mutex_id: Int);
    /// A new timer for `TON` and `TOF` (HMPL's `Timer t = TimerInit`); also resets one.
    ["HMPL 2.24"] fn TimerInit() -> Timer;
    /// On-delay timer on controller time: true once `IN` has been true for `PT` ms; false
    /// again when `IN` falls. `IN` is a boolean or a number (0 is false).
    ["HMPL 2.24"] fn TON(timer: Timer, IN: Bool, PT: Int) -> Bool;
    /// Off-delay timer on controller time: true as soon as `IN` is true; false `PT` ms after
    /// `IN` falls.
    ["HMPL 2.25"] fn TOF(timer: Timer, IN: Bool, PT: Int) -> Bool;

    // HMPL ch. 2: what the controller is; out-parameters are returned after the code.
    /// The firmware version, luamotion's own: `rc, ver` ("N/A" when it cannot be read).
    ["HMPL 2.11"] fn GetFirmwareVer() -> (Int, Str);
    /// The firmware file's date, `YYYY-MM-DD hh:mm:ss` UTC of the luamotion executable: `rc, date`.
    ["HMPL 2.12"] fn GetFirmwareDate() -> (Int, Str);
    /// A 64-bit hash of the luamotion executable (the same build gives the same hash):
    /// `rc, hash`, the 64 bits as a Lua integer.
    ["HMPL 2.13"] fn GetFirmwareHash() -> (Int, Int);
    /// The product model, the machine file's `[identity] model`: `rc, model`.
    ["HMPL 2.14"] fn GetModelNum() -> (Int, Str);
    /// The serial number, the machine file's `[identity] serial`: `rc, sn`.
    ["HMPL 2.15"] fn GetSerialNum() -> (Int, Str);
    /// 1 starts, 0 stops recording the scope: the event stream gets eMSG_START_HMI_SCOPE
    /// (0xB2C8) or eMSG_STOP_HMI_SCOPE (0xB2C9); `luamotion run --trace` records every
    /// cycle. 0, or 0x138F for another value.
    ["HMPL 2.17", ascii] fn SetHMIScope(start: Int) -> Int;

    // HMPL ch. 3: strings and memory, in the script process. A string is read as C reads
    // it, up to its first NUL byte; a string made longer than HMPL_STR_MAX_LEN (512) is
    // refused with 0x138D. Out-parameters and the new value of an in/out destination are
    // returned after the code; the arguments are never changed.
    /// `Print`'s formatting into a string: `count, text` (-1 and "" on a bad format or
    /// a text longer than 512).
    ["HMPL 3.3"] fn StringPrint(format: Str, args: Rest) -> (Int, Str);
    /// The length without the terminator: "hello world" is 11.
    ["HMPL 3.4", ascii] fn StringLen(str: Str) -> Int;
    /// True when the two strings are equal.
    ["HMPL 3.5", ascii] fn IsStringEqual(str1: Str, str2: Str) -> Bool;
    /// The offset of the first `character` (a one-character string or its byte code) in
    /// `str`, -1 when there is none.
    ["HMPL 3.6"] fn StrFindChar(str: Str, character: Any) -> Int;
    /// The offset of the first character of `str` in `char_set` (`complement_set` false)
    /// or not in it (true), -1 when there is none.
    ["HMPL 3.7", ascii] fn StrFindCharEx(str: Str, char_set: Str, complement_set: Bool) -> Int;
    /// The offset of the first `str2` in `str1`, -1 when there is none.
    ["HMPL 3.8", ascii] fn StrFindStr(str1: Str, str2: Str) -> Int;
    /// A copy of `source`: `rc, destination`.
    ["HMPL 3.9"] fn StringCopy(source: Str) -> (Int, Str);
    /// `copy_len` characters of `source` from `start_pos` (-1: to its end): `rc,
    /// destination`. 0x138F for a start or a length outside the string.
    ["HMPL 3.10"] fn StringCopyEx(source: Str, start_pos: Int, copy_len: Int) -> (Int, Str);
    /// `destination` with `source` appended: `rc, destination`.
    ["HMPL 3.11"] fn StringCat(destination: Str, source: Str) -> (Int, Str);
    /// `destination` with `copy_len` characters of `source` from `start_pos` (-1: to its
    /// end) appended: `rc, destination`.
    ["HMPL 3.12"] fn StringCatEx(destination: Str, source: Str, start_pos: Int, copy_len: Int) -> (Int, Str);
    /// The number at the start of the string, as C's `atof` reads it (0 when there is none).
    ["HMPL 3.13", ascii] fn StringToDouble(str: Str) -> Double;
    /// Copies the first `byte_num` bytes of `source` over `destination`: `rc, destination`.
    /// A table of integers is a C `int[]` (4 bytes each), one of floats a `double[]`
    /// (8 bytes); 0x138B when `byte_num` is past the end of either.
    ["HMPL 3.14"] fn MemoryCopy(destination: Memory, source: Memory, byte_num: Int) -> (Int, Memory);
    /// Sets the first `byte_num` bytes of `destination` to `value` (as a C `char`): `rc,
    /// destination`; `MemorySet({1, 2}, 1, 4)` gives `{16843009, 2}`.
    ["HMPL 3.15"] fn MemorySet(destination: Memory, value: Int, byte_num: Int) -> (Int, Memory);
    /// True when the first `byte_num` bytes of the two tables are equal (false past the
    /// end of either).
    ["HMPL 3.16"] fn IsMemoryEqual(memory_ptr1: Memory, memory_ptr2: Memory, byte_num: Int) -> Bool;

    // HMPL ch. 4: C libm in radians, in the script process.
    /// The sine of `x` radians.
    ["HMPL 4.1", ascii] fn sin(x: Double) -> Double;
    /// The cosine of `x` radians.
    ["HMPL 4.2", ascii] fn cos(x: Double) -> Double;
    /// The tangent of `x` radians.
    ["HMPL 4.3", ascii] fn tan(x: Double) -> Double;
    /// The arc sine, -π/2..π/2 (NaN outside -1..1).
    ["HMPL 4.4", ascii] fn asin(x: Double) -> Double;
    /// The arc cosine, 0..π (NaN outside -1..1).
    ["HMPL 4.5", ascii] fn acos(x: Double) -> Double;
    /// The arc tangent, -π/2..π/2.
    ["HMPL 4.6", ascii] fn atan(x: Double) -> Double;
    /// The arc tangent of y/x in the quadrant of (x, y), -π..π.
    ["HMPL 4.7", ascii] fn atan2(y: Double, x: Double) -> Double;
    /// The absolute value of an integer (a Lua error when it does not fit).
    ["HMPL 4.8", ascii] fn abs(x: Int) -> Int;
    /// The absolute value of a number.
    ["HMPL 4.9", ascii] fn fabs(x: Double) -> Double;
    /// The smallest integral value not less than `x`, as a float.
    ["HMPL 4.10", ascii] fn ceil(x: Double) -> Double;
    /// The largest integral value not greater than `x`, as a float.
    ["HMPL 4.11", ascii] fn floor(x: Double) -> Double;
    /// x·2^y; an overflow gives the largest double (with the sign of the result).
    ["HMPL 4.12", ascii] fn ldexp(x: Double, y: Int) -> Double;
    /// e^x; an overflow gives the largest double.
    ["HMPL 4.13", ascii] fn exp(x: Double) -> Double;
    /// x^y; an overflow gives the largest double (with the sign of the result).
    ["HMPL 4.14", ascii] fn pow(x: Double, y: Double) -> Double;
    /// The natural logarithm.
    ["HMPL 4.15", ascii] fn log(x: Double) -> Double;
    /// The base-10 logarithm.
    ["HMPL 4.16", ascii] fn log10(x: Double) -> Double;
    /// The square root.
    ["HMPL 4.17", ascii] fn sqrt(x: Double) -> Double;
    /// The cube root.
    ["HMPL 4.18", ascii] fn cbrt(x: Double) -> Double;
    /// sqrt(x² + y²) without undue overflow.
    ["HMPL 4.19", ascii] fn hypot(x: Double, y: Double) -> Double;

    // HMPL 17.3: controller variables by HCV id (the ids luamotion has: docs/api.md).
    /// The variable `hcv_id` (`0xCCIIVVVV`, HMPL 17.1): `value, result` with result 0, or
    /// -1 and value 0 for an id luamotion does not have or an axis or group that does
    /// not exist (a warning on stderr says which).
    ["HMPL 17.3.1"] fn GetConfigVar(hcv_id: Int) -> (Double, Int);
    /// Sets the variable `hcv_id` through the setter it belongs to: 0, the setter's code,
    /// 0x0001 for an id luamotion does not have, 0x0003 for a read-only one, 0x0004 for a
    /// value the variable cannot hold.
    ["HMPL 17.3.2"] fn SetConfigVar(hcv_id: Int, value: Double) -> Int;

    /// Adds the axes to the group in order (X, Y, Z, A, B, C; at most 9) and enables it,
    /// as AddAxisToGrp for each then EnableGroup. On a failure the axes it added are removed
    /// again and the code is returned.
    ["HMPL 8.3.3"] fn SetupGroup(group_id: Int, axis_ids: Rest) -> Int;

    // HMPL ch. 11: the user table, 512000 doubles shared by all tasks (indices from 0).
    /// Writes `num_data` values from the table `input` at `start_idx`. 0 or 0x138F.
    ["HMPL 11.2"] fn SetUserTable(start_idx: Int, num_data: Int, input: Doubles) -> Int;
    /// Reads `num_data` values at `start_idx`: `rc, values`.
    ["HMPL 11.3"] fn GetUserTable(start_idx: Int, num_data: Int) -> (Int, Doubles);
    /// Writes one value. 0 or 0x138F.
    ["HMPL 11.4", ascii] fn SetTableValue(index: Int, value: Double) -> Int;
    /// Reads one value.
    ["HMPL 11.5", ascii] fn GetTableValue(index: Int) -> Double;
    /// Saves a range to the controller's disk: the file is replaced whole or not at all.
    /// 0, 0x138F or 0x0139.
    ["HMPL 11.6", ascii] fn SaveUserTable(start_idx: Int, num_data: Int) -> Int;
    /// Loads a range from the controller's disk. 0, 0x138F or 0x0138 (nothing saved).
    ["HMPL 11.7", ascii] fn LoadUserTable(start_idx: Int, num_data: Int) -> Int;

    // Fatek FUN147: the PLC register image in the controller's shared memory, which the
    // boxes and the Modbus server use too (docs/fun147.md).
    /// Assembles a FUN147 step table (`001 SPD 5000`, `LIN ADR,500,400,,,Ut`, `WAIT TIME,100`,
    /// `GOTO NEXT`, `MEND`, `;` comments) and writes it at `sr` (0xA55C, N, 15 words a
    /// step). A text error is a Lua error with its line and column; nothing is written then.
    ["Fatek FUN147"] fn MHSPOLoad(sr: Str, text: Str) -> Int;
    /// The step table at `sr` as text; a Lua error naming the FUN147 code (34, 35, 36, …)
    /// when `sr` holds no valid table.
    ["Fatek FUN147"] fn MHSPOText(sr: Str) -> Str;
    /// A register: "R1000", "D4062" the 16-bit word 0..65535; "DR1000", "DD100" the signed
    /// 32-bit value of n (low word) and n+1 (high word). A Lua error for an address that
    /// does not exist.
    ["Fatek FUN147"] fn GetPlcReg(addr: Str) -> Int;
    /// Writes a register: a word 0..65535 (or -32768..-1 as its two's complement), a double
    /// word (DR, DD) -2^31..2^31-1. 0; a Lua error for an address or value that does not fit.
    ["Fatek FUN147"] fn SetPlcReg(addr: Str, value: Int) -> Int;
    /// A relay: "X0"-"X255", "Y0"-"Y255", "M0"-"M2001", "S0"-"S999".
    ["Fatek FUN147"] fn GetPlcRelay(addr: Str) -> Bool;
    /// Writes a relay (X too: the simulation has no input terminals). 0.
    ["Fatek FUN147"] fn SetPlcRelay(addr: Str, on: Bool) -> Int;

    // DXMC 8.3 FreePort: TCP sessions of the script process, framed by a start byte (none,
    // 0..0xFF or a 1-char string) and end bytes (none, a byte, CR_LF or a string of at most
    // 2), at most 1024 bytes of data a frame. Codes: 0 ok, 1 bad argument, 2 no such
    // session, 3 session id in use, 4 open failed, 5 not connected, 6 frame too long,
    // 7 send failed, 8 too many sessions (32 a task). Sessions end with the task.
    /// Listens on TCP `Port` (3000..10000) as session `SessionID`; one peer at a time, the
    /// next one is accepted when the last has gone. Listens on 127.0.0.1 unless the
    /// machine file's `[freeport] bind` names another address. 0 or 1, 3, 4, 8. The codes of all
    /// `FreePort.Eth` functions: 0 ok, 1 bad argument, 2 no such session, 3 session id in
    /// use, 4 open failed, 5 not connected, 6 frame too long, 7 send failed, 8 too many
    /// sessions (32 a task).
    ["DXMC 8.3 FreePort" as "FreePort.Eth.OpenAsServer"] fn EthOpenAsServer(SessionID: Int, Port: Int, SByte: Any, EByte: Any) -> Int;
    /// Connects to `IPAddr`:`Port` (3000..10000) as session `SessionID`, waiting at most 1 s.
    /// 0 or 1, 3, 4, 8.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.OpenAsClient"] fn EthOpenAsClient(SessionID: Int, IPAddr: Str, Port: Int, SByte: Any, EByte: Any) -> Int;
    /// Sends `Msg` as one frame: a string as its bytes, a number as its Lua text, a boolean
    /// as `true`/`false`, a table as its bytes 0..255. `code, Msg`: 0 or 1 (nil, a table
    /// not of bytes), 2, 5, 6 (more than 1024 bytes), 7.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.Tx"] fn EthTx(SessionID: Int, Msg: Any) -> (Int, Any);
    /// The next received frame without its start and end bytes, never waiting:
    /// `code, data, count`; `0, "", 0` when no frame is complete. 6 for a frame longer than
    /// 1024 bytes (dropped), 5 when no peer is connected and nothing is left, 2.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.Rx"] fn EthRx(SessionID: Int) -> (Int, Str, Int);
    /// Closes the session and frees its port. 0 or 2.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.Close"] fn EthClose(SessionID: Int) -> Int;
    /// Closes every session of the task. 0.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.CloseAll"] fn EthCloseAll() -> Int;
    /// Drops what was received and not yet read. 0 or 2.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.BuffClear"] fn EthBuffClear(SessionID: Int) -> Int;
    /// `0, ids`: the sessions of the task, ascending.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.GetSessions"] fn EthGetSessions() -> (Int, Doubles);
    /// 0 while a peer is connected, 5 when none is (yet), 2 for no such session.
    ["DXMC 8.3 FreePort" as "FreePort.Eth.ConnectCheck"] fn EthConnectCheck(SessionID: Int) -> Int;
    // HMPL 22.2.1, 22.2.2: the User ASCII server, served by the task that starts the agent.
    /// Starts the User ASCII agent: the task's process listens on the User ASCII port
    /// (`[ascii] user_port`, 4000) and hands every line a client sends to
    /// `parser(command)`; the string it returns goes back as a line (nil: an empty line; an
    /// error: `ERROR <message>`, and the agent lives on). Lines are served while the task
    /// waits (Sleep, Till, DELAY) and, once the program has returned, until the task is
    /// stopped. One agent controller-wide: 0, or 0x1392 while another task's agent runs;
    /// calling it again from the same task changes the parser.
    ["HMPL 22.2.1"] fn START_ASCII_AGENT(parser: Func) -> Int;
    /// Sends `message` (its first `length` bytes; all of it when `length` is nil) as a line
    /// to every client of the User ASCII agent. 0; 0x138D for more than 128 bytes; 0x1452
    /// when no agent runs.
    ["HMPL 22.2.2"] fn ASCII_ServerBroadcast(message: Str, length: Int or nil) -> Int;
    // DXMC 8.3 FreePort on serial port 1, the controller's pseudo-terminal (`[serial]` in
    // the machine file): start byte (none, 0..0xFF or a 1-char string), end (none, a byte,
    // a 1-char string or CR_LF), at most 256 data bytes a frame. Codes: those of
    // `FreePort.Eth` (0 ok, 1 bad argument, 6 frame too long) and 9 no such port (only
    // port 1), 10 no serial port (disabled, or the controller is gone), 11 line error
    // (the peer's frame or baud rate is not the port's: bytes dropped), 12 overrun (frames
    // dropped, the receive queue of 64 was full), 13 the port speaks Modbus: Init first.
    /// Switches port 1 to FreePort with these delimiters and `Protocol` (a FreePort code of
    /// parameter 5-1: 0x09..0x0E, 0x10, 0x12, 0x14, 0x17, 0x1A, 0x1D; omitted: the line's
    /// frame as it is) and clears the receive buffer: `code, P309`, the FreePort format
    /// word of parameter 5-5 (DCBAUZYX; `Init(1, ":", ";")` gives 0x00113B3A). 0 or 1, 9, 10.
    ["DXMC 8.3 FreePort" as "FreePort.Serial.Init"] fn SerialInit(port: Int, SrtByte: Any, EndByte: Any, Protocol: Any) -> (Int, Int);
    /// Sends `Msg` as one frame (converted as `FreePort.Eth.Tx` does): `code, Msg`. 0 or 1,
    /// 6 (more than 256 bytes), 9, 10, 13.
    ["DXMC 8.3 FreePort" as "FreePort.Serial.Tx"] fn SerialTx(port: Int, Msg: Any) -> (Int, Any);
    /// The next received frame without its start and end bytes, never waiting:
    /// `code, data, count`; `0, "", 0` when none is complete. 6 for a frame longer than 256
    /// bytes (dropped), 9, 10, 11, 12, 13.
    ["DXMC 8.3 FreePort" as "FreePort.Serial.Rx"] fn SerialRx(port: Int) -> (Int, Str, Int);
    // HMPL 22.2, 22.3: the task as a TCP client of an ASCII or a Modbus TCP server. Every
    // call returns 0 or a system error code; out-parameters are further returns. A call
    // waits at most 3 s (connect) or 2 s (the others) (docs/decisions.md).
    /// Connects to an ASCII server (`ip` an IP address, `port` a string): `rc, socket_id`.
    /// 0x17D5 failed (refused, bad address, 8 sockets open), 0x17D4 timeout.
    ["HMPL 22.2.3"] fn ASCII_ClientConnect(ip: Str, port: Str) -> (Int, Int);
    /// Receives what has arrived, up to `length` (1..512) bytes, waiting for the first:
    /// `rc, text`. 0x17DF failed (closed by the server, unknown socket, bad length),
    /// 0x17DE timeout.
    ["HMPL 22.2.4"] fn ASCII_ClientRecv(socket_id: Int, length: Int) -> (Int, Str);
    /// Sends the first `length` (0..512) bytes of `buffer` (fewer if it is shorter).
    /// 0x17E9 failed, 0x17E8 timeout.
    ["HMPL 22.2.5"] fn ASCII_ClientSend(socket_id: Int, length: Int, buffer: Str) -> Int;
    /// Closes the connection. 0x17D8 timeout, 0x138F unknown socket.
    ["HMPL 22.2.6"] fn ASCII_ClientDisconnect(socket_id: Int) -> Int;
    /// Connects to a Modbus TCP server at `ip` (port 502, or `"ip:port"`): `rc, socket_id`.
    /// 0x1839 failed (refused, bad address, 8 sockets open), 0x1838 timeout.
    ["HMPL 22.3.1"] fn Modbus_ClientConnect(ip: Str) -> (Int, Int);
    /// Closes the connection. 0x183C timeout, 0x138F unknown socket.
    ["HMPL 22.3.2"] fn Modbus_ClientDisconnect(socket_id: Int) -> Int;
    /// FC 03, 1..125 registers: `rc, bytes, use_length` (each register high byte first).
    /// 0x183D count out of range, 0x1840 failed (exception reply, lost connection),
    /// 0x183F timeout.
    ["HMPL 22.3.3"] fn Modbus_ClientRead_HoldReg(socket_id: Int, start_addr: Int, num_regs: Int) -> (Int, Bytes, Int);
    /// FC 04, 1..125 input registers, as `Modbus_ClientRead_HoldReg`.
    ["HMPL 22.3.4"] fn Modbus_ClientRead_InputReg(socket_id: Int, start_addr: Int, num_regs: Int) -> (Int, Bytes, Int);
    /// FC 01, 1..2000 coils: `rc, bytes, use_length`, eight a byte, the first in bit 0.
    ["HMPL 22.3.5"] fn Modbus_ClientRead_Coils(socket_id: Int, start_addr: Int, num_coils: Int) -> (Int, Bytes, Int);
    /// FC 02, 1..2000 discrete inputs, as `Modbus_ClientRead_Coils`.
    ["HMPL 22.3.6"] fn Modbus_ClientRead_Inputs(socket_id: Int, start_addr: Int, num_inputs: Int) -> (Int, Bytes, Int);
    /// FC 16, 1..123 registers from the table `write_data` (integers 0..65535): `rc, bytes,
    /// use_length`, the reply's start address and count. 0x183D for a count out of range or
    /// a short or bad table.
    ["HMPL 22.3.7"] fn Modbus_ClientWrite_HoldReg(socket_id: Int, start_addr: Int, num_regs: Int, write_data: Doubles) -> (Int, Bytes, Int);
    /// FC 15, 1..1968 coils: coil i is bit i % 16 of `write_data[i / 16 + 1]` (`{15}` sets
    /// four), otherwise as `Modbus_ClientWrite_HoldReg`.
    ["HMPL 22.3.8"] fn Modbus_ClientWrite_Coils(socket_id: Int, start_addr: Int, num_coils: Int, write_data: Doubles) -> (Int, Bytes, Int);

    // luamotion test: the expectations of a test program (`luamotion test`). A failed one
    // prints `file:line: expect_... failed: ...` and the program goes on; a program with a
    // failed expectation fails when it ends (docs/decisions.md). Each returns whether it held.
    /// Expects `actual == expected` as Lua compares them (3 equals 3.0; a table only itself).
    ["luamotion test"] fn expect_eq(actual: Any, expected: Any, message: Str or nil) -> Bool;
    /// Expects `|actual - expected| <= tolerance` (a NaN never is): `expect_near(GetPosFb(0), 100, 1e-3)`.
    ["luamotion test"] fn expect_near(actual: Double, expected: Double, tolerance: Double, message: Str or nil) -> Bool;
    /// Expects a true value (not false, nil or 0, as `Till` reads a condition).
    ["luamotion test"] fn expect_true(value: Any, message: Str or nil) -> Bool;
}
