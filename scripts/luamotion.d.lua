---@meta luamotion
-- Generated from the registry by `luamotion api lua`; do not edit.

---A timer for TON and TOF (HMPL 2.24).
---@class Timer
---@field Q boolean
---@field ET integer
---@field IN boolean

--- Enables (servo on) the axis by walking the drive's CiA 402 state machine; both axes
--- of a gantry pair. Returns at once; `Till(function() return IsEnabled(a) end)` waits.
---HMPL 5.2.1 (command (round trip to the core))
---@param axis_id integer
---@return integer
function Enable(axis_id) end

--- Disables (servo off) the axis and clears its path planning.
---HMPL 5.2.2 (command (round trip to the core))
---@param axis_id integer
---@return integer
function Disable(axis_id) end

--- Leaves ErrorStop once the cause is gone (a drive fault is reset too).
---HMPL 5.2.3 (command (round trip to the core))
---@param axis_id integer
---@return integer
function Reset(axis_id) end

--- Moves to an absolute position (mm or deg) with the axis' profile. In buffer mode 0 a
--- move under way is re-planned to the new target; in mode 1 it is queued.
---HMPL 5.2.4 (command (round trip to the core))
---@param axis_id integer
---@param pos number
---@return integer
function MoveAbs(axis_id, pos) end

--- Moves by a distance from the target under way (or from the reference at rest).
---HMPL 5.2.5 (command (round trip to the core))
---@param axis_id integer
---@param rel_dist number
---@return integer
function MoveRel(axis_id, rel_dist) end

--- Moves at a constant velocity until stopped; the sign is the direction.
---HMPL 5.2.6 (command (round trip to the core))
---@param axis_id integer
---@param vel number
---@return integer
function MoveVel(axis_id, vel) end

--- Produces a constant torque (N·m) in cyclic synchronous torque mode (`SetOpMode(a, 10)`).
---HMPL 5.2.7 (command (round trip to the core))
---@param axis_id integer
---@param torque_cmd number
---@return integer
function MoveTrq(axis_id, torque_cmd) end

--- Moves through position-velocity-time points (times in ms from 0, at most 50 points),
--- starting where the axis stands. The tables hold at least `num_pt` numbers each.
---HMPL 5.2.8 (command (round trip to the core))
---@param axis_id integer
---@param time number[]
---@param pos number[]
---@param vel number[]
---@param num_pt integer
---@return integer
function MovePVT(axis_id, time, pos, vel, num_pt) end

--- Decelerates to a stop and clears the path planning.
---HMPL 5.2.9 (command (round trip to the core))
---@param axis_id integer
---@return integer
function Stop(axis_id) end

--- Pauses the motion (velocity to 0), keeping it for `Resume`.
---HMPL 5.2.10 (command (round trip to the core))
---@param axis_id integer
---@return integer
function Halt(axis_id) end

--- Continues a halted motion to its target.
---HMPL 5.2.11 (command (round trip to the core))
---@param axis_id integer
---@return integer
function Resume(axis_id) end

--- Sets the profile velocity (mm/s or deg/s, > 0, at most the machine file's `max_vel`).
---HMPL 5.3.2 (command (round trip to the core))
---@param axis_id integer
---@param vel number
---@return integer
function SetVel(axis_id, vel) end

--- Sets the profile acceleration (mm/s² or deg/s², > 0, at most `max_acc`).
---HMPL 5.3.4 (command (round trip to the core))
---@param axis_id integer
---@param acc number
---@return integer
function SetAcc(axis_id, acc) end

--- Sets the acceleration from a time (ms, > 0): acc = vel / time.
---HMPL 5.3.5 (command (round trip to the core))
---@param axis_id integer
---@param acc_time number
---@return integer
function SetAccTime(axis_id, acc_time) end

--- Sets the profile deceleration (> 0, at most `max_acc`).
---HMPL 5.3.7 (command (round trip to the core))
---@param axis_id integer
---@param dec number
---@return integer
function SetDec(axis_id, dec) end

--- Sets the deceleration from a time (ms, > 0).
---HMPL 5.3.8 (command (round trip to the core))
---@param axis_id integer
---@param dec_time number
---@return integer
function SetDecTime(axis_id, dec_time) end

--- Sets the kill deceleration of StopAll and error stops (> 0).
---HMPL 5.3.10 (command (round trip to the core))
---@param axis_id integer
---@param kill_dec number
---@return integer
function SetKillDec(axis_id, kill_dec) end

--- Sets the software right (positive) limit.
---HMPL 5.3.12 (command (round trip to the core))
---@param axis_id integer
---@param right_limit_pos number
---@return integer
function SetSWRL(axis_id, right_limit_pos) end

--- Sets the software left (negative) limit.
---HMPL 5.3.14 (command (round trip to the core))
---@param axis_id integer
---@param left_limit_pos number
---@return integer
function SetSWLL(axis_id, left_limit_pos) end

--- Sets the smooth time (0..500 ms) that turns the profile into an S-curve; not while moving.
---HMPL 5.3.16 (command (round trip to the core))
---@param axis_id integer
---@param smooth_time number
---@return integer
function SetSMTime(axis_id, smooth_time) end

--- Makes the present position read `pos` by moving the axis' origin; not while moving,
--- synchronous, in a gantry or in error.
---HMPL 5.3.19 (command (round trip to the core))
---@param axis_id integer
---@param pos number
---@return integer
function SetPos(axis_id, pos) end

--- 1: ignore the hardware limits; 0: react to them (the default).
---HMPL 5.3.33 (command (round trip to the core))
---@param axis_id integer
---@param cmd integer
---@return integer
function IgnoreHWL(axis_id, cmd) end

--- 1: ignore the software limits; 0: react to them (the default).
---HMPL 5.3.34 (command (round trip to the core))
---@param axis_id integer
---@param cmd integer
---@return integer
function IgnoreSWL(axis_id, cmd) end

--- 1: ignore the position-error limit; 0: react to it (the default).
---HMPL 5.3.35 (command (round trip to the core))
---@param axis_id integer
---@param cmd integer
---@return integer
function IgnorePE(axis_id, cmd) end

--- Sets the velocity override, 0..100 %, applied to the move under way.
---HMPL 5.3.37 (command (round trip to the core))
---@param axis_id integer
---@param vel_scale number
---@return integer
function SetVelScale(axis_id, vel_scale) end

--- Sets the rollover length (> 0; 0 switches it off); only while disabled.
---HMPL 5.3.39 (command (round trip to the core))
---@param axis_id integer
---@param rollover_val number
---@return integer
function SetRollover(axis_id, rollover_val) end

--- Sets the drive mode: 8 cyclic synchronous position, 9 velocity, 10 torque.
---HMPL 5.3.41 (command (round trip to the core))
---@param axis_id integer
---@param op_mode integer
---@return integer
function SetOpMode(axis_id, op_mode) end

--- Sets the buffer mode: 0 a new move replaces the one under way, 1 moves queue up.
---HMPL 5.3.42 (command (round trip to the core))
---@param axis_id integer
---@param buf_mode integer
---@return integer
function SetBufferMode(axis_id, buf_mode) end

--- Sets the in-position window (> 0).
---HMPL 5.3.45 (command (round trip to the core))
---@param axis_id integer
---@param pos_window number
---@return integer
function SetPosWindow(axis_id, pos_window) end

--- Sets how long (ms, > 0) the feedback must stay in the window to be in position.
---HMPL 5.3.47 (command (round trip to the core))
---@param axis_id integer
---@param pos_window_time number
---@return integer
function SetPosWindowTime(axis_id, pos_window_time) end

--- Links a slave to a master; both must be enabled.
---HMPL 6.2 (command (round trip to the core))
---@param axis_master_id integer
---@param axis_slave_id integer
---@return integer
function EnableGear(axis_master_id, axis_slave_id) end

--- Removes the link (disengaging first).
---HMPL 6.3 (command (round trip to the core))
---@param axis_slave_id integer
---@return integer
function DisableGear(axis_slave_id) end

--- Engages the linked slave at a ratio (negative allowed): it follows the master's travel.
---HMPL 6.4 (command (round trip to the core))
---@param axis_master_id integer
---@param axis_slave_id integer
---@param gear_ratio number
---@return integer
function GearIn(axis_master_id, axis_slave_id, gear_ratio) end

--- Disengages the slave; it comes to rest with its deceleration.
---HMPL 6.5 (command (round trip to the core))
---@param axis_slave_id integer
---@return integer
function GearOut(axis_slave_id) end

--- Pairs a right-hand (linear) and a left-hand (yaw) axis; both must be disabled.
---HMPL 7.2 (command (round trip to the core))
---@param rhs_axis_id integer
---@param lhs_axis_id integer
---@return integer
function EnableGantryPair(rhs_axis_id, lhs_axis_id) end

--- Splits the pair of an axis; both must be disabled.
---HMPL 7.3 (command (round trip to the core))
---@param axis_id integer
---@return integer
function DisableGantryPair(axis_id) end

--- Enables the group; every axis in it must be enabled first (0x82II03F2 otherwise).
---HMPL 8.2.1 (command (round trip to the core))
---@param group_id integer
---@return integer
function EnableGroup(group_id) end

--- Disables the group; its axes stay grouped and enabled, its path planning is cleared.
---HMPL 8.2.2 (command (round trip to the core))
---@param group_id integer
---@return integer
function DisableGroup(group_id) end

--- Group Error Stop -> Group Standby, once every cause is gone (axes enabled, no error stop).
---HMPL 8.2.3 (command (round trip to the core))
---@param group_id integer
---@return integer
function ResetGroup(group_id) end

--- Decelerates along the path and clears the group's command buffer.
---HMPL 8.2.4 (command (round trip to the core))
---@param group_id integer
---@return integer
function StopGroup(group_id) end

--- Pauses the group's motion (path velocity to 0), keeping the path for `ResumeGroup`.
---HMPL 8.2.5 (command (round trip to the core))
---@param group_id integer
---@return integer
function HaltGroup(group_id) end

--- Continues a halted group along the same path.
---HMPL 8.2.6 (command (round trip to the core))
---@param group_id integer
---@return integer
function ResumeGroup(group_id) end

--- Jogs the tool in MCS along X, Y, Z, A, B or C (`carte_dir` 0..5) at a signed
--- velocity (mm/s or deg/s) until `StopGroup` or a jog velocity of 0.
---HMPL 8.2.7 (command (round trip to the core))
---@param group_id integer
---@param carte_dir integer
---@param jog_vel number
---@return integer
function JogGroup(group_id, carte_dir, jog_vel) end

--- Jogs one axis of the group (`grp_axis` 0..8, in the order added) at a signed velocity.
---HMPL 8.2.8 (command (round trip to the core))
---@param group_id integer
---@param grp_axis integer
---@param jog_vel number
---@return integer
function JogGroupAxis(group_id, grp_axis, jog_vel) end

--- Linear interpolation to (X, Y) in the group's coordinate system.
---HMPL 8.2.9 (command (round trip to the core))
---@param group_id integer
---@param end_x number
---@param end_y number
---@return integer
function LineAbs2D(group_id, end_x, end_y) end

--- Linear interpolation to (X, Y, Z).
---HMPL 8.2.10 (command (round trip to the core))
---@param group_id integer
---@param end_x number
---@param end_y number
---@param end_z number
---@return integer
function LineAbs3D(group_id, end_x, end_y, end_z) end

--- Linear interpolation by (dX, dY) from where the queued path ends.
---HMPL 8.2.11 (command (round trip to the core))
---@param group_id integer
---@param distance_x number
---@param distance_y number
---@return integer
function LineRel2D(group_id, distance_x, distance_y) end

--- Linear interpolation by (dX, dY, dZ).
---HMPL 8.2.12 (command (round trip to the core))
---@param group_id integer
---@param distance_x number
---@param distance_y number
---@param distance_z number
---@return integer
function LineRel3D(group_id, distance_x, distance_y, distance_z) end

--- Arc through a border point to an end point (three points; less than a full turn).
---HMPL 8.2.13 (command (round trip to the core))
---@param group_id integer
---@param border_x number
---@param border_y number
---@param end_x number
---@param end_y number
---@return integer
function Arc2D(group_id, border_x, border_y, end_x, end_y) end

--- Clockwise arc about a center to an end point on the same radius.
---HMPL 8.2.14 (command (round trip to the core))
---@param group_id integer
---@param center_x number
---@param center_y number
---@param end_x number
---@param end_y number
---@return integer
function ArcCW2D(group_id, center_x, center_y, end_x, end_y) end

--- Counter-clockwise arc about a center to an end point on the same radius.
---HMPL 8.2.15 (command (round trip to the core))
---@param group_id integer
---@param center_x number
---@param center_y number
---@param end_x number
---@param end_y number
---@return integer
function ArcCCW2D(group_id, center_x, center_y, end_x, end_y) end

--- Arc about a center by `angle` degrees: > 0 counter-clockwise, < 0 clockwise.
---HMPL 8.2.16 (command (round trip to the core))
---@param group_id integer
---@param center_x number
---@param center_y number
---@param angle number
---@return integer
function ArcAngle2D(group_id, center_x, center_y, angle) end

--- Circular motion about a center to an end point; `turns` >= 0 counter-clockwise, < 0
--- clockwise; total angle θ + (turns-1)·360 for turns >= 1 (0 as 1), θ + turns·360 below.
---HMPL 8.2.17 (command (round trip to the core))
---@param group_id integer
---@param center_x number
---@param center_y number
---@param end_x number
---@param end_y number
---@param turns integer
---@return integer
function Circle2D(group_id, center_x, center_y, end_x, end_y, turns) end

--- Appends an axis to the group (X, Y, Z, A, B, C order; at most 9); the group is disabled.
---HMPL 8.3.1 (command (round trip to the core))
---@param group_id integer
---@param axis_id integer
---@return integer
function AddAxisToGrp(group_id, axis_id) end

--- Removes the axis added last; the group is disabled.
---HMPL 8.3.2 (command (round trip to the core))
---@param group_id integer
---@return integer
function RemoveAxisFromGrp(group_id) end

--- Disables the group and removes all its axes.
---HMPL 8.3.4 (command (round trip to the core))
---@param group_id integer
---@return integer
function UngrpAllAxes(group_id) end

--- Sets the linear (TCP) profile: vel 0..5000 mm/s, acc and dec > 0..50000 mm/s²,
--- smooth time 0..500 ms. Defaults 100, 5000, 5000, 50.
---HMPL 8.3.6 (command (round trip to the core))
---@param group_id integer
---@param max_velocity number
---@param max_acceleration number
---@param max_deceleration number
---@param smooth_time number
---@return integer
function SetGrpMotionProfile(group_id, max_velocity, max_acceleration, max_deceleration, smooth_time) end

--- Sets the angular profile: vel 0..7200 deg/s, acc and dec > 0..72000 deg/s², smooth
--- time 0..500 ms. Defaults 360, 1800, 1800, 50.
---HMPL 8.3.7 (command (round trip to the core))
---@param group_id integer
---@param max_velocity number
---@param max_acceleration number
---@param max_deceleration number
---@param smooth_time number
---@return integer
function SetGrpAngMotionProfile(group_id, max_velocity, max_acceleration, max_deceleration, smooth_time) end

--- Sets the kinematics: 1 Cartesian (2 SCARA, 3 wafer, 4 articulated are not available).
---HMPL 8.3.9 (command (round trip to the core))
---@param group_id integer
---@param kin_type integer
---@return integer
function SetGrpKin(group_id, kin_type) end

--- Sets the linear profile velocity, 0..5000 mm/s.
---HMPL 8.3.11 (command (round trip to the core))
---@param group_id integer
---@param vel number
---@return integer
function SetGrpVel(group_id, vel) end

--- Sets the linear profile acceleration, > 0..50000 mm/s².
---HMPL 8.3.13 (command (round trip to the core))
---@param group_id integer
---@param acc number
---@return integer
function SetGrpAcc(group_id, acc) end

--- Sets the acceleration from a time (ms > 0): acc = vel / time.
---HMPL 8.3.14 (command (round trip to the core))
---@param group_id integer
---@param acc_time number
---@return integer
function SetGrpAccTime(group_id, acc_time) end

--- Sets the linear profile deceleration, > 0..50000 mm/s².
---HMPL 8.3.16 (command (round trip to the core))
---@param group_id integer
---@param dec number
---@return integer
function SetGrpDec(group_id, dec) end

--- Sets the deceleration from a time (ms > 0): dec = vel / time.
---HMPL 8.3.17 (command (round trip to the core))
---@param group_id integer
---@param dec_time number
---@return integer
function SetGrpDecTime(group_id, dec_time) end

--- Sets the smooth time, 0..500 ms.
---HMPL 8.3.19 (command (round trip to the core))
---@param group_id integer
---@param smooth_time number
---@return integer
function SetGrpSMTime(group_id, smooth_time) end

--- Selects the coordinate system of later targets: `CS_MCS`, or flags such as
--- `CS_OFFSET | CS_WCS2 | CS_PCS`.
---HMPL 8.3.21 (command (round trip to the core))
---@param group_id integer
---@param coord_sys integer
---@return integer
function SetGrpCoordSys(group_id, coord_sys) end

--- Sets the buffer mode of later commands: BM_BUFF, BM_ABORT, BM_LOW, BM_PREV, BM_NEXT,
--- BM_HIGH or BM_LOOKAHEAD.
---HMPL 8.3.23 (command (round trip to the core))
---@param group_id integer
---@param buffer_mode integer
---@return integer
function SetGrpBufferMode(group_id, buffer_mode) end

--- Sets the transition mode of later junctions: TM_NONE, TM_CONST_VEL, TM_CORNER_DIST,
--- TM_MAX_CORNER_DEV or TM_MAX_CORNER_CURV.
---HMPL 8.3.25 (command (round trip to the core))
---@param group_id integer
---@param trans_mode integer
---@return integer
function SetGrpTransMode(group_id, trans_mode) end

--- Sets the transition parameters (table 8.3.26.1): velocity (0, 5000) mm/s, distance
--- and deviation mm > 0, curvature (0, 1e7) 1/mm; the ones the mode does not use may be 0.
---HMPL 8.3.26 (command (round trip to the core))
---@param group_id integer
---@param trans_vel number
---@param trans_dis number
---@param trans_dev number
---@param trans_curv number
---@return integer
function SetGrpTransPrm(group_id, trans_vel, trans_dis, trans_dev, trans_curv) end

--- Sets the velocity override, 0..100 %, applied along the path under way.
---HMPL 8.3.28 (command (round trip to the core))
---@param group_id integer
---@param vel_scale number
---@return integer
function SetGrpVelScale(group_id, vel_scale) end

--- The transform {X, Y, Z mm, A, B, C deg} of `CS_PCS`, `CS_WCSn` or `CS_OFFSET`: `rc, trans_param`.
---HMPL 8.3.30 (command (round trip to the core))
---@param group_id integer
---@param coord_sys integer
---@return integer
---@return number[]
function GetGrpCoordTrans(group_id, coord_sys) end

--- Sets the transform {X, Y, Z mm, A, B, C deg} (fixed-frame roll-pitch-yaw) of
--- `CS_PCS`, `CS_WCSn` or `CS_OFFSET`.
---HMPL 8.3.31 (command (round trip to the core))
---@param group_id integer
---@param coord_sys integer
---@param trans_param number[]
---@return integer
function SetGrpCoordTrans(group_id, coord_sys, trans_param) end

--- The commanded pose {X, Y, Z, A, B, C} in a coordinate system: `rc, pose_cmd`.
---HMPL 8.3.32 (command (round trip to the core))
---@param group_id integer
---@param coord_sys integer
---@return integer
---@return number[]
function GetGrpPoseCmd(group_id, coord_sys) end

--- The pose from the axes' feedback in a coordinate system: `rc, pose_fb`.
---HMPL 8.3.33 (command (round trip to the core))
---@param group_id integer
---@param coord_sys integer
---@return integer
---@return number[]
function GetGrpPoseFb(group_id, coord_sys) end

--- Sets a look-ahead parameter: 0 corner acceleration (default 5000 mm/s²), 1 arc
--- acceleration (default 100 mm/s²), 2 chord error (default 0: off), mm.
---HMPL 8.3.34 (command (round trip to the core))
---@param group_id integer
---@param prm_id integer
---@param value number
---@return integer
function SetGrpLookAheadPrm(group_id, prm_id, value) end

--- Sets the command buffer's size to 2^queue_size (0..10; default 512); only when empty.
---HMPL 8.3.35 (command (round trip to the core))
---@param group_id integer
---@param queue_size integer
---@return integer
function SetGrpQueueSize(group_id, queue_size) end

--- Linear motion to a 6-D target {X, Y, Z, A, B, C} in `coord_sys`.
---HMPL 8.5.1 (command (round trip to the core))
---@param group_id integer
---@param target_pos number[]
---@param motion_profile number[]
---@param coord_sys integer
---@param buff_mode integer
---@param trans_mode integer
---@param trans_par number[]
---@return integer
function LineAbs(group_id, target_pos, motion_profile, coord_sys, buff_mode, trans_mode, trans_par) end

--- Linear motion by a 6-D distance.
---HMPL 8.5.2 (command (round trip to the core))
---@param group_id integer
---@param relative_dist number[]
---@param motion_profile number[]
---@param coord_sys integer
---@param buff_mode integer
---@param trans_mode integer
---@param trans_par number[]
---@return integer
function LineRel(group_id, relative_dist, motion_profile, coord_sys, buff_mode, trans_mode, trans_par) end

--- 3-D circle about `center_pos` with the rotation of `normal_vector` (right-hand rule),
--- `turns` as Circle2D, to a 6-D target; a target off the circle's plane makes a helix.
---HMPL 8.5.3 (command (round trip to the core))
---@param group_id integer
---@param center_pos number[]
---@param normal_vector number[]
---@param turns integer
---@param target_pos number[]
---@param motion_profile number[]
---@param coord_sys integer
---@param buff_mode integer
---@param trans_mode integer
---@param trans_par number[]
---@return integer
function CircleAbs(group_id, center_pos, normal_vector, turns, target_pos, motion_profile, coord_sys, buff_mode, trans_mode, trans_par) end

--- As CircleAbs with a target relative to where the queued path ends (the center is absolute).
---HMPL 8.5.4 (command (round trip to the core))
---@param group_id integer
---@param center_pos number[]
---@param normal_vector number[]
---@param turns integer
---@param relative_dist number[]
---@param motion_profile number[]
---@param coord_sys integer
---@param buff_mode integer
---@param trans_mode integer
---@param trans_par number[]
---@return integer
function CircleRel(group_id, center_pos, normal_vector, turns, relative_dist, motion_profile, coord_sys, buff_mode, trans_mode, trans_par) end

--- Runs the drive's homing (needs 0x6060/0x6061 mapped) and returns when it is over:
--- 0 when homed, else the error (0x83II0424 timeout, 0x83II042E failed, 0x83II00D2 while
--- compensating).
---HMPL 20.2 (command (round trip to the core))
---@param axis_id integer
---@return integer
function MoveHome(axis_id) end

--- Sets the homing method: 1, 2, 7-14, 17, 18, 23-30, 33, 34, 37 (default 33).
---HMPL 20.3 (command (round trip to the core))
---@param axis_id integer
---@param method integer
---@return integer
function SetHomeMethod(axis_id, method) end

--- Sets the fast homing speed, searching the switch (default 20).
---HMPL 20.4 (command (round trip to the core))
---@param axis_id integer
---@param fast_vel number
---@return integer
function SetHomeSwitchVel(axis_id, fast_vel) end

--- Sets the slow homing speed, searching the index (default 5).
---HMPL 20.5 (command (round trip to the core))
---@param axis_id integer
---@param slow_vel number
---@return integer
function SetHomeZeroVel(axis_id, slow_vel) end

--- Sets the homing acceleration (default 2000).
---HMPL 20.6 (command (round trip to the core))
---@param axis_id integer
---@param acc number
---@return integer
function SetHomeAcc(axis_id, acc) end

--- Sets the position the home reads after homing (default 0).
---HMPL 20.7 (command (round trip to the core))
---@param axis_id integer
---@param offset number
---@return integer
function SetHomeOffset(axis_id, offset) end

--- Sets the homing timeout, ms (default 120000).
---HMPL 20.8 (command (round trip to the core))
---@param axis_id integer
---@param timeout integer
---@return integer
function SetHomeTimeout(axis_id, timeout) end

--- Sets the homed flag by hand (for homing routines of one's own).
---HMPL 20.9 (command (round trip to the core))
---@param axis_id integer
---@param is_homed integer
---@return integer
function SetHomedStatus(axis_id, is_homed) end

--- Enables the compensation set up for the axis (its values are read from the user
--- table now); only while the axis is disabled (0x83II006E), after a setup (0x83II0190),
--- with the axis and its reference axes homed (0x83II0064). It applies once enabled.
---HMPL 14.2 (command (round trip to the core))
---@param axis_id integer
---@return integer
function EnableComp(axis_id) end

--- Disables the compensation and clears its setup; only while the axis is disabled
--- (0x83II006E). The reference becomes the position the axis stands at.
---HMPL 14.3 (command (round trip to the core))
---@param axis_id integer
---@return integer
function DisableComp(axis_id) end

--- A 1-D table: `num_pt` values (2 or more) for reference positions
--- `base_val + k * interval` of axis `ref_axis_id`.
---HMPL 14.4 (command (round trip to the core))
---@param axis_id integer
---@param start_idx integer
---@param base_val number
---@param interval number
---@param num_pt integer
---@param ref_axis_id integer
---@return integer
function SetupComp(axis_id, start_idx, base_val, interval, num_pt, ref_axis_id) end

--- A 2-D table: `base_val`, `interval`, `num_pt` and `ref_axis_id` are tables of 2, one
--- entry per dimension; as many values as the product of `num_pt`.
---HMPL 14.5 (command (round trip to the core))
---@param axis_id integer
---@param start_idx integer
---@param base_val number[]
---@param interval number[]
---@param num_pt number[]
---@param ref_axis_id number[]
---@return integer
function SetupComp2D(axis_id, start_idx, base_val, interval, num_pt, ref_axis_id) end

--- A 3-D table: as `SetupComp2D` with tables of 3; linear only.
---HMPL 14.6 (command (round trip to the core))
---@param axis_id integer
---@param start_idx integer
---@param base_val number[]
---@param interval number[]
---@param num_pt number[]
---@param ref_axis_id number[]
---@return integer
function SetupComp3D(axis_id, start_idx, base_val, interval, num_pt, ref_axis_id) end

--- 0: linear between the points (the default), 1: natural cubic spline (1-D and 2-D);
--- not while active.
---HMPL 14.8 (command (round trip to the core))
---@param axis_id integer
---@param alg_type integer
---@return integer
function SetCompAlgType(axis_id, alg_type) end

--- Clears the axis' last error.
---HMPL 18.4 (command (round trip to the core))
---@param axis_id integer
---@return integer
function ClearAxisLastErr(axis_id) end

--- Clears a group's last error.
---HMPL 18.6 (command (round trip to the core))
---@param group_id integer
---@return integer
function ClearGrpLastErr(group_id) end

--- Reads a drive object by SDO. Returns its value (sign-extended), or -1 on failure
--- (ambiguous with a real -1, as in HMPL; use `ReadSDOEx` to tell them apart).
---HMPL 17.2.1 (command (round trip to the core))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@param obj_length integer
---@return integer
function ReadSDO(slv_id, obj_index, obj_subindex, obj_length) end

--- Reads a drive object by SDO: `rc, bytes` with rc 0 or -1 and the object's bytes as a
--- table of integers (little-endian).
---HMPL 17.2.2 (command (round trip to the core))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@param obj_length integer
---@return integer
---@return integer[]
function ReadSDOEx(slv_id, obj_index, obj_subindex, obj_length) end

--- Writes a drive object by SDO. Returns 0, or -1 on failure.
---HMPL 17.2.3 (command (round trip to the core))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@param obj_length integer
---@param obj_value integer
---@return integer
function WriteSDO(slv_id, obj_index, obj_subindex, obj_length, obj_value) end

--- Writes a drive object by SDO from bytes (a table of integers or a string). Returns 0 or -1.
---HMPL 17.2.4 (command (round trip to the core))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@param obj_length integer
---@param obj_value integer[]|string
---@return integer
function WriteSDOEx(slv_id, obj_index, obj_subindex, obj_length, obj_value) end

--- Writes an object mapped in the RxPDO. The motion kernel may overwrite it in the same
--- cycle if it writes that object too. Returns 0 or -1.
---HMPL 17.2.7 (command (round trip to the core))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@param obj_value integer
---@return integer
function WritePDO(slv_id, obj_index, obj_subindex, obj_value) end

--- Forces an RxPDO object: the value overrides every other writer until `ReleasePDO`.
---HMPL 17.2.8 (command (round trip to the core))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@param obj_value integer
---@return integer
function ForceWritePDO(slv_id, obj_index, obj_subindex, obj_value) end

--- Releases a forced RxPDO object. Returns 0 or -1.
---HMPL 17.2.9 (command (round trip to the core))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@return integer
function ReleasePDO(slv_id, obj_index, obj_subindex) end

--- Simulator only: puts a drive into Fault with an error code of the CoE manual's table
--- 4-16 (e.g. 0x3110 over voltage). Returns 0, or -1 for a code the drive model lacks.
---luamotion sim (command (round trip to the core))
---@param slv_id integer
---@param error_code integer
---@return integer
function SimDriveFault(slv_id, error_code) end

--- Simulator only: the electrical level of controller input `gpi_idx` (1..8), before
--- inversion, as a switch wired to it would set it. Returns 0 or -1.
---luamotion sim (command (round trip to the core))
---@param gpi_idx integer
---@param on_off integer
---@return integer
function SimSetGPI(gpi_idx, on_off) end

--- Simulator only: the switch on input `gpi_idx` (1..) of a digital I/O terminal
--- (`[[slaves]] device = "digital_io"`), as wired to it. Returns 0, or -1 for no such
--- terminal or input (a drive's inputs are not simulated).
---luamotion sim (command (round trip to the core))
---@param slv_slot_id integer
---@param gpi_idx integer
---@param on_off integer
---@return integer
function SimSetSlvGPI(slv_slot_id, gpi_idx, on_off) end

--- Disables every axis and clears its path planning.
---HMPL 2.7 (command (round trip to the core))
---@return integer
function DisableAll() end

--- Stops every axis with its kill deceleration; they stay enabled; the plans are cleared.
---HMPL 2.8 (command (round trip to the core))
---@return integer
function StopAll() end

--- Emergency stop: stops every task (the caller too: the call never returns) and
--- disables every axis. Motion commands then fail with 0x0064 until the axis is enabled again.
---HMPL 2.9 (command (round trip to the core))
function EStop() end

--- Rescans the EtherCAT segment: every slave back to Pre-Op, configured and brought to
--- Op again, the slaves' table renewed. 0, or 0x138C while an axis or a group is enabled
--- or the controller is not in a state that allows it (docs/decisions.md, "System").
---HMPL 2.16 (command (round trip to the core))
---@return integer
function ScanNetwork() end

--- Sets output `gpo_idx` on (1) or off (0).
---HMPL 9.2.1 (command (round trip to the core))
---@param gpo_idx integer
---@param on_off integer
---@return integer
function SetGPO(gpo_idx, on_off) end

--- Toggles output `gpo_idx`.
---HMPL 9.2.2 (command (round trip to the core))
---@param gpo_idx integer
---@return integer
function ToggleGPO(gpo_idx) end

--- Sets all outputs from a bitmask (bit 0 is pin 1).
---HMPL 9.2.3 (command (round trip to the core))
---@param all_gpo_state integer
---@return integer
function SetAllGPO(all_gpo_state) end

--- Inverts input `gpi_idx` (1) or not (0).
---HMPL 9.2.4 (command (round trip to the core))
---@param gpi_idx integer
---@param invert integer
---@return integer
function SetGPIInvert(gpi_idx, invert) end

--- Inverts output `gpo_idx` (1) or not (0).
---HMPL 9.2.5 (command (round trip to the core))
---@param gpo_idx integer
---@param invert integer
---@return integer
function SetGPOInvert(gpo_idx, invert) end

--- Sets output `gpo_idx` of a slave on (1) or off (0).
---HMPL 9.3.1 (command (round trip to the core))
---@param slv_slot_id integer
---@param gpo_idx integer
---@param on_off integer
---@return integer
function SetSlvGPO(slv_slot_id, gpo_idx, on_off) end

--- Toggles output `gpo_idx` of a slave.
---HMPL 9.3.2 (command (round trip to the core))
---@param slv_slot_id integer
---@param gpo_idx integer
---@return integer
function ToggleSlvGPO(slv_slot_id, gpo_idx) end

--- Sets all outputs of a slave from a bitmask (bit 0 is output 1).
---HMPL 9.3.3 (command (round trip to the core))
---@param slv_slot_id integer
---@param all_gpo_state integer
---@return integer
function SetSlvAllGPO(slv_slot_id, all_gpo_state) end

--- Arms touch probe 1 with the function `SetTouchProbe1Func` set (by default the
--- index, single, rising edge); a single-trigger probe latches again once re-enabled.
---HMPL 13.2 (command (round trip to the core))
---@param axis_id integer
---@return integer
function EnableTouchProbe1(axis_id) end

--- Arms touch probe 2 (as `EnableTouchProbe1`).
---HMPL 13.3 (command (round trip to the core))
---@param axis_id integer
---@return integer
function EnableTouchProbe2(axis_id) end

--- Switches touch probe 1 off; its latched state is cleared.
---HMPL 13.4 (command (round trip to the core))
---@param axis_id integer
---@return integer
function DisableTouchProbe1(axis_id) end

--- Switches touch probe 2 off.
---HMPL 13.5 (command (round trip to the core))
---@param axis_id integer
---@return integer
function DisableTouchProbe2(axis_id) end

--- Touch probe 1's signal (`tp_input` 0 the drive's probe input, 1 the encoder index),
--- trigger (`cont_trigger` 0 first edge only, 1 every edge) and edge (`detect_edge` 0
--- rising, 1 falling); applied at once, re-arming an enabled probe.
---HMPL 13.12 (command (round trip to the core))
---@param axis_id integer
---@param tp_input integer
---@param cont_trigger integer
---@param detect_edge integer
---@return integer
function SetTouchProbe1Func(axis_id, tp_input, cont_trigger, detect_edge) end

--- Touch probe 2's function (as `SetTouchProbe1Func`).
---HMPL 13.13 (command (round trip to the core))
---@param axis_id integer
---@param tp_input integer
---@param cont_trigger integer
---@param detect_edge integer
---@return integer
function SetTouchProbe2Func(axis_id, tp_input, cont_trigger, detect_edge) end

--- Chooses the input whose rising edge is the E-stop (default 8; 0: none).
---HMPL 9.2.6 (command (round trip to the core))
---@param gpi_idx integer
---@return integer
function BindEMO(gpi_idx) end

--- Turns the axis' vibration suppression filter (a notch at `SetAxisVsf`'s frequency) on;
--- 0x83II00C8 while input shaping is on.
---HMPL 15.2 (command (round trip to the core))
---@param axis_id integer
---@return integer
function EnableAxisVsf(axis_id) end

--- Turns the axis' VSF off.
---HMPL 15.3 (command (round trip to the core))
---@param axis_id integer
---@return integer
function DisableAxisVsf(axis_id) end

--- Sets the VSF's frequency (0.1..200 Hz, below 0.45 of the cycle rate) and damping ratio
--- (0.7..1.5, 1.0 recommended: the notch's width).
---HMPL 15.4 (command (round trip to the core))
---@param axis_id integer
---@param frequency number
---@param damping_ratio number
---@return integer
function SetAxisVsf(axis_id, frequency, damping_ratio) end

--- Turns the axis' input shaper on; 0x83II0064 while the VSF is on.
---HMPL 15.5 (command (round trip to the core))
---@param axis_id integer
---@return integer
function EnableAxisInShape(axis_id) end

--- Turns the axis' input shaper off.
---HMPL 15.6 (command (round trip to the core))
---@param axis_id integer
---@return integer
function DisableAxisInShape(axis_id) end

--- Sets the axis' input shaper: the load's frequency (1.5..300 Hz, default 5.5), damping
--- ratio (0..0.3, default 0.03) and type (1 SHAPER_NORMAL: ZV, 0 SHAPER_ROBUST: ZVD).
---HMPL 15.7 (command (round trip to the core))
---@param axis_id integer
---@param frequency number
---@param damping_ratio number
---@param shaper_type integer
---@return integer
function SetAxisInShape(axis_id, frequency, damping_ratio, shaper_type) end

--- Turns the group's input shaper on (every coordinate of its path).
---HMPL 15.8 (command (round trip to the core))
---@param group_id integer
---@return integer
function EnableGrpInShape(group_id) end

--- Turns the group's input shaper off.
---HMPL 15.9 (command (round trip to the core))
---@param group_id integer
---@return integer
function DisableGrpInShape(group_id) end

--- Sets the group's input shaper: frequency 3.0..300 Hz, damping 0..0.3, type as
--- SetAxisInShape (0x82II005A for another type).
---HMPL 15.10 (command (round trip to the core))
---@param group_id integer
---@param frequency number
---@param damping_ratio number
---@param shaper_type integer
---@return integer
function SetGrpInShape(group_id, frequency, damping_ratio, shaper_type) end

--- Sets an analog input's conversion type (`HMPL_DAC_*` of table 10.1.1, optionally
--- `| HMPL_DAC_SIGNED`).
---HMPL 10.2.1 (command (round trip to the core))
---@param slv_slot_id integer
---@param ai_idx integer
---@param range_type integer
---@return integer
function SetSlvAIType(slv_slot_id, ai_idx, range_type) end

--- Sets an analog output's conversion type; not `HMPL_DAC_NONE` while it is bound.
---HMPL 10.2.2 (command (round trip to the core))
---@param slv_slot_id integer
---@param ao_idx integer
---@param range_type integer
---@return integer
function SetSlvAOType(slv_slot_id, ao_idx, range_type) end

--- Writes an analog output's 16-bit word: 0..65535, or -32768..32767 as two's complement.
---HMPL 10.2.3 (command (round trip to the core))
---@param slv_slot_id integer
---@param ao_idx integer
---@param ao_raw_val integer
---@return integer
function SetSlvAORaw(slv_slot_id, ao_idx, ao_raw_val) end

--- Writes an analog output in its conversion type's units (within its range; the top
--- value gives the top word).
---HMPL 10.2.4 (command (round trip to the core))
---@param slv_slot_id integer
---@param ao_idx integer
---@param ao_val number
---@return integer
function SetSlvAO(slv_slot_id, ao_idx, ao_val) end

--- Chooses the variable an analog output follows: `HMPL_AXIS_n | HMPL_<VAR>` (REF_POS,
--- REF_VEL, REF_ACC, POS_FB, VEL_FB, ACC_FB, CUR_FB); needs a conversion type.
---HMPL 10.4.1 (command (round trip to the core))
---@param slv_slot_id integer
---@param ao_idx integer
---@param var_id integer
---@return integer
function SetSlvAOMonitor(slv_slot_id, ao_idx, var_id) end

--- Binds (1) or frees (0) an analog output: every cycle it is var * scale + offset in its
--- type's units, saturated at the range's ends. Binding needs `SetSlvAOMonitor` first.
---HMPL 10.4.2 (command (round trip to the core))
---@param slv_slot_id integer
---@param ao_idx integer
---@param ao_en_bind integer
---@param ao_scale number
---@param ao_offset number
---@return integer
function SetSlvAOParam(slv_slot_id, ao_idx, ao_en_bind, ao_scale, ao_offset) end

--- Simulator only: the word an analog terminal's converter reads on input `ai_idx`
--- (0..65535, or -32768..32767), as a signal wired to it would make it. 0 or 0x138F.
---luamotion sim (command (round trip to the core))
---@param slv_slot_id integer
---@param ai_idx integer
---@param ai_raw_val integer
---@return integer
function SimSetSlvAIRaw(slv_slot_id, ai_idx, ai_raw_val) end

--- Starts a task's program in its own process; returns once it runs. 0x0107 no such
--- task id, 0x0108 already running, 0x010A no program configured.
---HMPL 16.2 (command (round trip to the core))
---@param task_id integer
---@return integer
function StartTask(task_id) end

--- Starts a task at a function of its program: the program's top level runs first (it
--- should only declare), then `func_name()`. 0x0109 when the program has no such function.
---HMPL 16.3 (command (round trip to the core))
---@param task_id integer
---@param func_name string
---@return integer
function StartTaskFunc(task_id, func_name) end

--- Stops a task: its motion reacts as its fault reaction says, its mutexes are released,
--- its process ends. 0x010B when it is not running.
---HMPL 16.4 (command (round trip to the core))
---@param task_id integer
---@return integer
function StopTask(task_id) end

--- Stops every task, the caller too: the call never returns.
---HMPL 16.5 (command (round trip to the core))
function StopAllTask() end

--- Declares the FUN147 box of group `gp` (Gp, 0 or 1): its step table at `sr` (SR), its
--- working registers WR+0..WR+8 at `wr` ("R2000", "D0": R0-R3839, R5000-R8071,
--- D0-D3999), the relays it reads every cycle (EN, PAU, ABT) and writes (ACT, ERR, DN):
--- "X0"-"X255", "Y0"-"Y255", "M0"-"M2001", "S0"-"S999". Psi is axis i, one pulse 0.001
--- axis unit; box Gp moves through group 14 + Gp. Declaring a group's box again
--- replaces it (stopped first). 0, or 0x138F for an operand that does not exist.
---Fatek FUN147 (command (round trip to the core))
---@param gp integer
---@param sr string
---@param wr string
---@param en string
---@param pau string
---@param abt string
---@param act string
---@param err string
---@param dn string
---@return integer
function MHSPO(gp, sr, wr, en, pau, abt, act, err, dn) end

--- Stops the box of group `gp` at once, frees its axes and removes it. 0, or 0x138F
--- for a `gp` other than 0 and 1.
---Fatek FUN147 (command (round trip to the core))
---@param gp integer
---@return integer
function MHSPOFree(gp) end

--- Starts a pass over the points set last (equidistant or the position array); the axis
--- must be homed (0x83II0064). The pass ends by itself after its last point.
---HMPL 12.2 (command (round trip to the core))
---@param axis_id integer
---@return integer
function EnablePT(axis_id) end

--- Ends the pass under way; the points not reached give no pulse.
---HMPL 12.3 (command (round trip to the core))
---@param axis_id integer
---@return integer
function DisablePT(axis_id) end

--- The first point of equidistant PT; a start above the end triggers on negative motion.
---HMPL 12.5 (command (round trip to the core))
---@param axis_id integer
---@param start_pos number
---@return integer
function SetPT_StartPos(axis_id, start_pos) end

--- The last point of equidistant PT: no pulse beyond it.
---HMPL 12.6 (command (round trip to the core))
---@param axis_id integer
---@param end_pos number
---@return integer
function SetPT_EndPos(axis_id, end_pos) end

--- The spacing of equidistant PT (> 0). The axis' speed must stay below interval x 16 kHz
--- (HMPL 12.1.1): a point reached in the same drive sample as the one before gives no
--- pulse and is counted as missed.
---HMPL 12.7 (command (round trip to the core))
---@param axis_id integer
---@param interval number
---@return integer
function SetPT_Interval(axis_id, interval) end

--- The pulse width, 20..80000 ns in steps of 20 (E1 drive). A controller GPO shows each
--- pulse for at least one cycle.
---HMPL 12.8 (command (round trip to the core))
---@param axis_id integer
---@param width_ns integer
---@return integer
function SetPT_PulseWidth(axis_id, width_ns) end

--- Point `index` (0..255) of the position array, and chooses array PT.
---HMPL 12.9 (command (round trip to the core))
---@param axis_id integer
---@param index integer
---@param trigger_pos number
---@return integer
function SetPT_PosArray(axis_id, index, trigger_pos) end

--- State word `index` (0..7): bit k of word k/32 is point k's output, 1 a pulse, 0 none
--- (all 1 until set).
---HMPL 12.10 (command (round trip to the core))
---@param axis_id integer
---@param index integer
---@param state integer
---@return integer
function SetPT_StateArray(axis_id, index, state) end

--- The array index (0..255) the pass starts at; above the end index, it runs backwards
--- and triggers on negative motion. Chooses array PT.
---HMPL 12.11 (command (round trip to the core))
---@param axis_id integer
---@param index integer
---@return integer
function SetPT_StartIndex(axis_id, index) end

--- The array index (0..255) the pass ends at. Chooses array PT.
---HMPL 12.12 (command (round trip to the core))
---@param axis_id integer
---@param index integer
---@return integer
function SetPT_EndIndex(axis_id, index) end

--- Pulse `n` (from 0) of the last pass: its position and the controller time (ms,
--- interpolated within the cycle) its point was crossed; the first 256 pulses are kept.
--- 0x83II012C for a pulse that was not given.
---luamotion sim (command (round trip to the core))
---@param axis_id integer
---@param n integer
---@return integer
---@return number
---@return number
function GetPTPulse(axis_id, n) end

--- The profile velocity.
---HMPL 5.3.1 (query (local snapshot))
---@param axis_id integer
---@return number
function GetVel(axis_id) end

--- The profile acceleration.
---HMPL 5.3.3 (query (local snapshot))
---@param axis_id integer
---@return number
function GetAcc(axis_id) end

--- The profile deceleration.
---HMPL 5.3.6 (query (local snapshot))
---@param axis_id integer
---@return number
function GetDec(axis_id) end

--- The kill deceleration.
---HMPL 5.3.9 (query (local snapshot))
---@param axis_id integer
---@return number
function GetKillDec(axis_id) end

--- The software right limit.
---HMPL 5.3.11 (query (local snapshot))
---@param axis_id integer
---@return number
function GetSWRL(axis_id) end

--- The software left limit.
---HMPL 5.3.13 (query (local snapshot))
---@param axis_id integer
---@return number
function GetSWLL(axis_id) end

--- The smooth time, ms.
---HMPL 5.3.15 (query (local snapshot))
---@param axis_id integer
---@return number
function GetSMTime(axis_id) end

--- How long the last move took, ms.
---HMPL 5.3.17 (query (local snapshot))
---@param axis_id integer
---@return number
function GetMoveTime(axis_id) end

--- How long the last move took from its end to in position, ms.
---HMPL 5.3.18 (query (local snapshot))
---@param axis_id integer
---@return number
function GetSettlingTime(axis_id) end

--- Position feedback.
---HMPL 5.3.20 (query (local snapshot))
---@param axis_id integer
---@return number
function GetPosFb(axis_id) end

--- Position feedback with the compensation in it, as the drive reports it; `GetPosFb`
--- is the feedback without it, in the reference's coordinates.
---HMPL 5.3.21 (query (local snapshot))
---@param axis_id integer
---@return number
function GetPosFbComp(axis_id) end

--- The offset `SetPos` put between the axis and the drive.
---HMPL 5.3.22 (query (local snapshot))
---@param axis_id integer
---@return number
function GetPosOffset(axis_id) end

--- Position error: output minus feedback.
---HMPL 5.3.23 (query (local snapshot))
---@param axis_id integer
---@return number
function GetPosErr(axis_id) end

--- Velocity feedback.
---HMPL 5.3.24 (query (local snapshot))
---@param axis_id integer
---@return number
function GetVelFb(axis_id) end

--- Velocity error.
---HMPL 5.3.25 (query (local snapshot))
---@param axis_id integer
---@return number
function GetVelErr(axis_id) end

--- Current feedback, A (needs 0x6077 mapped).
---HMPL 5.3.26 (query (local snapshot))
---@param axis_id integer
---@return number
function GetCurrFb(axis_id) end

--- Reference position: the profile generator's output.
---HMPL 5.3.27 (query (local snapshot))
---@param axis_id integer
---@return number
function GetRefPos(axis_id) end

--- Reference velocity.
---HMPL 5.3.28 (query (local snapshot))
---@param axis_id integer
---@return number
function GetRefVel(axis_id) end

--- Reference acceleration.
---HMPL 5.3.29 (query (local snapshot))
---@param axis_id integer
---@return number
function GetRefAcc(axis_id) end

--- Position output: reference plus compensation.
---HMPL 5.3.30 (query (local snapshot))
---@param axis_id integer
---@return number
function GetPosOut(axis_id) end

--- Velocity output.
---HMPL 5.3.31 (query (local snapshot))
---@param axis_id integer
---@return number
function GetVelOut(axis_id) end

--- Acceleration output.
---HMPL 5.3.32 (query (local snapshot))
---@param axis_id integer
---@return number
function GetAccOut(axis_id) end

--- The number of axes.
---HMPL 5.3.36 (query (local snapshot))
---@return integer
function GetAxisNum() end

--- The velocity override, %.
---HMPL 5.3.38 (query (local snapshot))
---@param axis_id integer
---@return number
function GetVelScale(axis_id) end

--- Whole turns counted in rollover mode.
---HMPL 5.3.40 (query (local snapshot))
---@param axis_id integer
---@return integer
function GetRolloverTurns(axis_id) end

--- The buffer mode, 0 or 1.
---HMPL 5.3.43 (query (local snapshot))
---@param axis_id integer
---@return integer
function GetBufferMode(axis_id) end

--- Moves waiting in the queue.
---HMPL 5.3.44 (query (local snapshot))
---@param axis_id integer
---@return integer
function GetCmdNum(axis_id) end

--- The in-position window.
---HMPL 5.3.46 (query (local snapshot))
---@param axis_id integer
---@return number
function GetPosWindow(axis_id) end

--- The in-position time, ms.
---HMPL 5.3.48 (query (local snapshot))
---@param axis_id integer
---@return number
function GetPosWindowTime(axis_id) end

--- True when the axis is enabled (drive in Operation enabled).
---HMPL 5.4.1 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsEnabled(axis_id) end

--- True while the profile generator still emits new positions.
---HMPL 5.4.2 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsMoving(axis_id) end

--- True when the feedback has stayed within the position window for the window time.
---HMPL 5.4.3 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsInPos(axis_id) end

--- True in ErrorStop.
---HMPL 5.4.4 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsErrorStop(axis_id) end

--- True for an axis of a gantry pair.
---HMPL 5.4.5 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsGantry(axis_id) end

--- True for an axis in a group.
---HMPL 5.4.6 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsGrouped(axis_id) end

--- True when the axis follows a master (gear slave or group).
---HMPL 5.4.7 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsSync(axis_id) end

--- True while the hardware left (negative) limit is active (0x60FD bit 0).
---HMPL 5.4.8 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsHWLL(axis_id) end

--- True while the hardware right (positive) limit is active (0x60FD bit 1).
---HMPL 5.4.9 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsHWRL(axis_id) end

--- True once the software left limit stopped the axis.
---HMPL 5.4.10 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsSWLL(axis_id) end

--- True once the software right limit stopped the axis.
---HMPL 5.4.11 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsSWRL(axis_id) end

--- True when the drive reports a fault.
---HMPL 5.4.12 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsDriveErr(axis_id) end

--- True once the position error exceeded its limit.
---HMPL 5.4.13 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsPosErr(axis_id) end

--- True when error compensation is active on the axis.
---HMPL 5.4.14 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsCompActive(axis_id) end

--- True while the axis accelerates.
---HMPL 5.4.15 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsAcc(axis_id) end

--- The engaged gear ratio (0 when not engaged).
---HMPL 6.6 (query (local snapshot))
---@param axis_slave_id integer
---@return number
function GetGearRatio(axis_slave_id) end

--- True when the slave is engaged.
---HMPL 6.7 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsInGear(axis_id) end

--- True when the axis is a gear master.
---HMPL 6.8 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsGearMaster(axis_id) end

--- True when the axis is a gear slave.
---HMPL 6.9 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsGearSlave(axis_id) end

--- The gantry pair's id, -1 when not in a pair.
---HMPL 7.4 (query (local snapshot))
---@param axis_id integer
---@return integer
function GetGantryPairID(axis_id) end

--- True when the two axes form a pair.
---HMPL 7.5 (query (local snapshot))
---@param axis_id_1 integer
---@param axis_id_2 integer
---@return boolean
function IsGantryPair(axis_id_1, axis_id_2) end

--- True once homing completed (or `SetHomedStatus(a, 1)`).
---HMPL 20.10 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsHomed(axis_id) end

--- True while homing runs.
---HMPL 20.11 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsHoming(axis_id) end

--- True while the home switch is active (0x60FD bit 2).
---HMPL 20.12 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsHomeSwitch(axis_id) end

--- The last system error code (0x0000EEEE; 0: none).
---HMPL 18.2 (query (local snapshot))
---@return integer
function GetSystemLastErr() end

--- The axis' last error as a 32-bit code `0x83IIEEEE` (0: none).
---HMPL 18.3 (query (local snapshot))
---@param axis_id integer
---@return integer
function GetAxisLastErr(axis_id) end

--- A group's last error `0x82IIEEEE` (0: none).
---HMPL 18.5 (query (local snapshot))
---@param group_id integer
---@return integer
function GetGrpLastErr(group_id) end

--- The drive's own error code (0x603F).
---HMPL 18.7 (query (local snapshot))
---@param axis_id integer
---@return integer
function GetDriveErr(axis_id) end

--- The compensation added to the axis' reference this cycle (0 when none).
---HMPL 14.7 (query (local snapshot))
---@param axis_id integer
---@return number
function GetCompPos(axis_id) end

--- Reads an object mapped in the process data (TxPDO or RxPDO). Returns its value, or -1
--- when it is not mapped.
---HMPL 17.2.5 (query (local snapshot))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@return integer
function ReadPDO(slv_id, obj_index, obj_subindex) end

--- Reads a mapped object: `rc, bytes` with rc 0 or -1.
---HMPL 17.2.6 (query (local snapshot))
---@param slv_id integer
---@param obj_index integer
---@param obj_subindex integer
---@return integer
---@return integer[]
function ReadPDOEx(slv_id, obj_index, obj_subindex) end

--- True while the controller is initialising (never, once scripts run).
---HMPL 2.1 (query (local snapshot))
---@return boolean
function IsSystemInit() end

--- True when the system runs and EtherCAT is in Op: motion and PDO functions work.
---HMPL 2.2 (query (local snapshot))
---@return boolean
function IsSystemOper() end

--- True when the system runs with EtherCAT in Pre-Op (mailbox only).
---HMPL 2.3 (query (local snapshot))
---@return boolean
function IsSystemPreOp() end

--- True when the system is in error, e.g. EtherCAT start-up stopped short of Op.
---HMPL 2.4 (query (local snapshot))
---@return boolean
function IsSystemError() end

--- The master's EtherCAT state: 1 Init, 2 Pre-Op, 4 Safe-Op, 8 Op.
---HMPL 2.5 (query (local snapshot))
---@return integer
function GetECATSt() end

--- A slave's EtherCAT state: 1, 2, 4 or 8 (-1 for no such slave).
---HMPL 2.6 (query (local snapshot))
---@param slv_id integer
---@return integer
function GetSlvECATSt(slv_id) end

--- The number of slaves on the network.
---HMPL 2.10 (query (local snapshot))
---@return integer
function GetSlaveNum() end

--- Channels of a slave (`slv_id | HMPL_SLOT_n`) by type: 1 digital inputs, 2 digital
--- outputs, 3 analog inputs, 4 analog outputs (-1 for no such slave or type).
---HMPL 21.1 (query (local snapshot))
---@param slv_slot_id integer
---@param ch_type integer
---@return integer
function GetSlvChNum(slv_slot_id, ch_type) end

--- The number of slots (modules) of a slave; a drive has none.
---HMPL 21.2 (query (local snapshot))
---@param slv_id integer
---@return integer
function GetSlvSlotNum(slv_id) end

--- Controller input `gpi_idx` (1..8) after inversion: 1 on, 0 off, -1 no such input.
---HMPL 9.4.1 (query (local snapshot))
---@param gpi_idx integer
---@return integer
function GetGPI(gpi_idx) end

--- Controller output `gpo_idx`: 1 on, 0 off, -1 no such output.
---HMPL 9.4.2 (query (local snapshot))
---@param gpo_idx integer
---@return integer
function GetGPO(gpo_idx) end

--- All inputs as a bitmask (inputs 1 and 4 on: 9).
---HMPL 9.4.3 (query (local snapshot))
---@return integer
function GetAllGPI() end

--- All outputs as a bitmask (outputs 2 and 3 on: 6).
---HMPL 9.4.4 (query (local snapshot))
---@return integer
function GetAllGPO() end

--- The inverted inputs as a bitmask.
---HMPL 9.4.5 (query (local snapshot))
---@return integer
function GetAllGPIInvertSt() end

--- The inverted outputs as a bitmask.
---HMPL 9.4.6 (query (local snapshot))
---@return integer
function GetAllGPOInvertSt() end

--- Input `gpi_idx` of a slave: 1 on, 0 off.
---HMPL 9.5.1 (query (local snapshot))
---@param slv_slot_id integer
---@param gpi_idx integer
---@return integer
function GetSlvGPI(slv_slot_id, gpi_idx) end

--- Output `gpo_idx` of a slave as the master last sent it: 1 on, 0 off.
---HMPL 9.5.2 (query (local snapshot))
---@param slv_slot_id integer
---@param gpo_idx integer
---@return integer
function GetSlvGPO(slv_slot_id, gpo_idx) end

--- All inputs of a slave as a bitmask (inputs 1 and 4 on: 9).
---HMPL 9.5.3 (query (local snapshot))
---@param slv_slot_id integer
---@return integer
function GetSlvAllGPI(slv_slot_id) end

--- All outputs of a slave as a bitmask (outputs 2 and 3 on: 6).
---HMPL 9.5.4 (query (local snapshot))
---@param slv_slot_id integer
---@return integer
function GetSlvAllGPO(slv_slot_id) end

--- The inputs from `start_idx` on: bit k is input start_idx + k (start 8, inputs 8 and 11 on: 9).
---HMPL 9.5.5 (query (local snapshot))
---@param slv_slot_id integer
---@param start_idx integer
---@return integer
function GetSlvAllGPIByStartIdx(slv_slot_id, start_idx) end

--- The outputs from `start_idx` on: bit k is output start_idx + k (start 8, outputs 9 and 10 on: 6).
---HMPL 9.5.6 (query (local snapshot))
---@param slv_slot_id integer
---@param start_idx integer
---@return integer
function GetSlvAllGPOByStartIdx(slv_slot_id, start_idx) end

--- An analog input's conversion type (`HMPL_DAC_NONE` until set).
---HMPL 10.3.1 (query (local snapshot))
---@param slv_slot_id integer
---@param ai_idx integer
---@return integer
function GetSlvAIType(slv_slot_id, ai_idx) end

--- An analog output's conversion type.
---HMPL 10.3.2 (query (local snapshot))
---@param slv_slot_id integer
---@param ao_idx integer
---@return integer
function GetSlvAOType(slv_slot_id, ao_idx) end

--- An analog input's word: 0..65535, or signed with `HMPL_DAC_SIGNED`.
---HMPL 10.3.3 (query (local snapshot))
---@param slv_slot_id integer
---@param ai_idx integer
---@return integer
function GetSlvAIRaw(slv_slot_id, ai_idx) end

--- An analog input in its conversion type's units.
---HMPL 10.3.4 (query (local snapshot))
---@param slv_slot_id integer
---@param ai_idx integer
---@return number
function GetSlvAI(slv_slot_id, ai_idx) end

--- An analog output's word as the master last sent it: 0..65535, or signed.
---HMPL 10.3.5 (query (local snapshot))
---@param slv_slot_id integer
---@param ao_idx integer
---@return integer
function GetSlvAORaw(slv_slot_id, ao_idx) end

--- An analog output in its conversion type's units.
---HMPL 10.3.6 (query (local snapshot))
---@param slv_slot_id integer
---@param ao_idx integer
---@return number
function GetSlvAO(slv_slot_id, ao_idx) end

--- The scale of an analog output's binding (1 until set).
---HMPL 10.4.3 (query (local snapshot))
---@param slv_slot_id integer
---@param ao_idx integer
---@return number
function GetSlvAOScale(slv_slot_id, ao_idx) end

--- The offset of an analog output's binding (0 until set).
---HMPL 10.4.4 (query (local snapshot))
---@param slv_slot_id integer
---@param ao_idx integer
---@return number
function GetSlvAOOffset(slv_slot_id, ao_idx) end

--- 1 when an analog output follows a controller variable, else 0.
---HMPL 10.4.5 (query (local snapshot))
---@param slv_slot_id integer
---@param ao_idx integer
---@return integer
function IsSlvAOBound(slv_slot_id, ao_idx) end

--- 1 while touch probe 1 is enabled.
---HMPL 13.6 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsTouchProbe1Enabled(axis_id) end

--- 1 while touch probe 2 is enabled.
---HMPL 13.7 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsTouchProbe2Enabled(axis_id) end

--- 1 once touch probe 1 latched its edge since it was enabled (or its function set).
---HMPL 13.8 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsTouchProbe1Triggered(axis_id) end

--- 1 once touch probe 2 latched its edge.
---HMPL 13.9 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsTouchProbe2Triggered(axis_id) end

--- `rc, pos`: the position (mm or deg, in the axis' coordinates as the feedback) touch
--- probe 1 latched on its edge, the last one in continuous mode; 0 before any.
---HMPL 13.10 (query (local snapshot))
---@param axis_id integer
---@return integer
---@return number
function GetTouchProbe1Pos(axis_id) end

--- `rc, pos` of touch probe 2.
---HMPL 13.11 (query (local snapshot))
---@param axis_id integer
---@return integer
---@return number
function GetTouchProbe2Pos(axis_id) end

--- The group of an axis, -1 when it is in none.
---HMPL 8.3.5 (query (local snapshot))
---@param axis_id integer
---@return integer
function GetGroupID(axis_id) end

--- The kinematics id (1 Cartesian).
---HMPL 8.3.8 (query (local snapshot))
---@param group_id integer
---@return integer
function GetGrpKin(group_id) end

--- The linear profile velocity, mm/s.
---HMPL 8.3.10 (query (local snapshot))
---@param group_id integer
---@return number
function GetGrpVel(group_id) end

--- The linear profile acceleration, mm/s².
---HMPL 8.3.12 (query (local snapshot))
---@param group_id integer
---@return number
function GetGrpAcc(group_id) end

--- The linear profile deceleration, mm/s².
---HMPL 8.3.15 (query (local snapshot))
---@param group_id integer
---@return number
function GetGrpDec(group_id) end

--- The smooth time, ms.
---HMPL 8.3.18 (query (local snapshot))
---@param group_id integer
---@return number
function GetGrpSMTime(group_id) end

--- The coordinate system flags of later targets.
---HMPL 8.3.20 (query (local snapshot))
---@param group_id integer
---@return integer
function GetGrpCoordSys(group_id) end

--- The buffer mode of later commands.
---HMPL 8.3.22 (query (local snapshot))
---@param group_id integer
---@return integer
function GetGrpBufferMode(group_id) end

--- The transition mode of later junctions.
---HMPL 8.3.24 (query (local snapshot))
---@param group_id integer
---@return integer
function GetGrpTransMode(group_id) end

--- Commands in the group's buffer, the one under way included.
---HMPL 8.3.27 (query (local snapshot))
---@param group_id integer
---@return integer
function GetGrpCmdNum(group_id) end

--- The velocity override, 0..100 %.
---HMPL 8.3.29 (query (local snapshot))
---@param group_id integer
---@return number
function GetGrpVelScale(group_id) end

--- True while the group is enabled.
---HMPL 8.4.1 (query (local snapshot))
---@param group_id integer
---@return boolean
function IsGrpEnabled(group_id) end

--- True while the group's path generator still outputs positions.
---HMPL 8.4.2 (query (local snapshot))
---@param group_id integer
---@return boolean
function IsGrpMoving(group_id) end

--- True when the group stands still and every axis in it is in position.
---HMPL 8.4.3 (query (local snapshot))
---@param group_id integer
---@return boolean
function IsGrpInPos(group_id) end

--- True in Group Error Stop.
---HMPL 8.4.4 (query (local snapshot))
---@param group_id integer
---@return boolean
function IsGrpErrorStop(group_id) end

--- True unless the task is starting or running.
---HMPL 16.6 (query (local snapshot))
---@param task_id integer
---@return boolean
function IsTaskStop(task_id) end

--- True while a PT pass runs (enabled and points left).
---HMPL 12.4 (query (local snapshot))
---@param axis_id integer
---@return boolean
function IsPTEnabled(axis_id) end

--- Pulses given in the axis' last PT pass.
---luamotion sim (query (local snapshot))
---@param axis_id integer
---@return integer
function GetPTPulseNum(axis_id) end

--- Points of the last pass reached in the same drive sample as the pulse before (the
--- axis faster than interval x 16 kHz, HMPL 12.1.1): no pulse was given for them.
---luamotion sim (query (local snapshot))
---@param axis_id integer
---@return integer
function GetPTMissedNum(axis_id) end

--- Suspends the task for `ms` milliseconds of controller time.
---HMPL 2.18 (script process)
---@param ms integer
function Sleep(ms) end

--- Suspends the task until `condition()` returns a true value (not false, nil or 0).
--- The condition is evaluated once per controller cycle.
---HMPL 19.3 (script process)
---@param condition fun(): any
function Till(condition) end

--- Writes a formatted line to the message window (`%d %i %u %x %c %s %f %e %g %%`).
--- Returns the number of characters written.
---HMPL 3.2 (script process)
---@param format string
---@param ... any
---@return integer
function Print(format, ...) end

--- DRL: writes a string to the program's console.
---DXMC 8.3 DRL (script process)
---@param text string
function my_print(text) end

--- DRL: suspends the program for a number of seconds (fractions allowed) of controller time.
---DXMC 8.3 DRL (script process)
---@param seconds number
function DELAY(seconds) end

--- DRL: word `address` of the Modbus user areas, 0..65535: DV 0x0000..0x2FFF (volatile)
--- or DH 0x8000..0xAFFF (kept across restarts). A Lua error outside them.
---DXMC A.1 (script process)
---@param address integer
---@return integer
function ReadModbusWord(address) end

--- DRL: writes word `address` of DV or DH; the Modbus clients read it at once. 0, or
--- 0x138F for an address outside DV and DH or a value outside 0..65535.
---DXMC A.1 (script process)
---@param address integer
---@param value integer
---@return integer
function WriteModbusWord(address, value) end

--- Sends event `evt_id` (0..65535) to the tools following the event stream. Blocks
--- while the task sends faster than 1000 per second on average. Returns 0.
---HMPL 2.19 (script process)
---@param evt_id integer
---@return integer
function SendEvent(evt_id) end

--- Sends a formatted message (as `Print`, at most 128 characters; longer ones are
--- refused with 0x138D) to the event stream; throttled like `SendEvent`.
---HMPL 2.20 (script process)
---@param format string
---@param ... any
---@return integer
function SendMsgEvent(format, ...) end

--- Gives the processor to other programs for a moment.
---HMPL 2.21 (script process)
function RunScheduler() end

--- Takes mutex `mutex_id` (0..7), waiting while another task holds it. Taking it twice
--- stops the task with 0x13EC. A task that stops releases its mutexes.
---HMPL 2.22 (script process)
---@param mutex_id integer
function MutexLock(mutex_id) end

--- Releases mutex `mutex_id` if this task holds it; otherwise does nothing.
---HMPL 2.23 (script process)
---@param mutex_id integer
function MutexUnlock(mutex_id) end

--- A new timer for `TON` and `TOF` (HMPL's `Timer t = TimerInit`); also resets one.
---HMPL 2.24 (script process)
---@return Timer
function TimerInit() end

--- On-delay timer on controller time: true once `IN` has been true for `PT` ms; false
--- again when `IN` falls. `IN` is a boolean or a number (0 is false).
---HMPL 2.24 (script process)
---@param timer Timer
---@param IN boolean|number
---@param PT integer
---@return boolean
function TON(timer, IN, PT) end

--- Off-delay timer on controller time: true as soon as `IN` is true; false `PT` ms after
--- `IN` falls.
---HMPL 2.25 (script process)
---@param timer Timer
---@param IN boolean|number
---@param PT integer
---@return boolean
function TOF(timer, IN, PT) end

--- The firmware version, luamotion's own: `rc, ver` ("N/A" when it cannot be read).
---HMPL 2.11 (script process)
---@return integer
---@return string
function GetFirmwareVer() end

--- The firmware file's date, `YYYY-MM-DD hh:mm:ss` UTC of the luamotion executable: `rc, date`.
---HMPL 2.12 (script process)
---@return integer
---@return string
function GetFirmwareDate() end

--- A 64-bit hash of the luamotion executable (the same build gives the same hash):
--- `rc, hash`, the 64 bits as a Lua integer.
---HMPL 2.13 (script process)
---@return integer
---@return integer
function GetFirmwareHash() end

--- The product model, the machine file's `[identity] model`: `rc, model`.
---HMPL 2.14 (script process)
---@return integer
---@return string
function GetModelNum() end

--- The serial number, the machine file's `[identity] serial`: `rc, sn`.
---HMPL 2.15 (script process)
---@return integer
---@return string
function GetSerialNum() end

--- 1 starts, 0 stops recording the scope: the event stream gets eMSG_START_HMI_SCOPE
--- (0xB2C8) or eMSG_STOP_HMI_SCOPE (0xB2C9); `luamotion run --trace` records every
--- cycle. 0, or 0x138F for another value.
---HMPL 2.17 (script process)
---@param start integer
---@return integer
function SetHMIScope(start) end

--- `Print`'s formatting into a string: `count, text` (-1 and "" on a bad format or
--- a text longer than 512).
---HMPL 3.3 (script process)
---@param format string
---@param ... any
---@return integer
---@return string
function StringPrint(format, ...) end

--- The length without the terminator: "hello world" is 11.
---HMPL 3.4 (script process)
---@param str string
---@return integer
function StringLen(str) end

--- True when the two strings are equal.
---HMPL 3.5 (script process)
---@param str1 string
---@param str2 string
---@return boolean
function IsStringEqual(str1, str2) end

--- The offset of the first `character` (a one-character string or its byte code) in
--- `str`, -1 when there is none.
---HMPL 3.6 (script process)
---@param str string
---@param character any
---@return integer
function StrFindChar(str, character) end

--- The offset of the first character of `str` in `char_set` (`complement_set` false)
--- or not in it (true), -1 when there is none.
---HMPL 3.7 (script process)
---@param str string
---@param char_set string
---@param complement_set boolean|number
---@return integer
function StrFindCharEx(str, char_set, complement_set) end

--- The offset of the first `str2` in `str1`, -1 when there is none.
---HMPL 3.8 (script process)
---@param str1 string
---@param str2 string
---@return integer
function StrFindStr(str1, str2) end

--- A copy of `source`: `rc, destination`.
---HMPL 3.9 (script process)
---@param source string
---@return integer
---@return string
function StringCopy(source) end

--- `copy_len` characters of `source` from `start_pos` (-1: to its end): `rc,
--- destination`. 0x138F for a start or a length outside the string.
---HMPL 3.10 (script process)
---@param source string
---@param start_pos integer
---@param copy_len integer
---@return integer
---@return string
function StringCopyEx(source, start_pos, copy_len) end

--- `destination` with `source` appended: `rc, destination`.
---HMPL 3.11 (script process)
---@param destination string
---@param source string
---@return integer
---@return string
function StringCat(destination, source) end

--- `destination` with `copy_len` characters of `source` from `start_pos` (-1: to its
--- end) appended: `rc, destination`.
---HMPL 3.12 (script process)
---@param destination string
---@param source string
---@param start_pos integer
---@param copy_len integer
---@return integer
---@return string
function StringCatEx(destination, source, start_pos, copy_len) end

--- The number at the start of the string, as C's `atof` reads it (0 when there is none).
---HMPL 3.13 (script process)
---@param str string
---@return number
function StringToDouble(str) end

--- Copies the first `byte_num` bytes of `source` over `destination`: `rc, destination`.
--- A table of integers is a C `int[]` (4 bytes each), one of floats a `double[]`
--- (8 bytes); 0x138B when `byte_num` is past the end of either.
---HMPL 3.14 (script process)
---@param destination integer[]|number[]
---@param source integer[]|number[]
---@param byte_num integer
---@return integer
---@return integer[]|number[]
function MemoryCopy(destination, source, byte_num) end

--- Sets the first `byte_num` bytes of `destination` to `value` (as a C `char`): `rc,
--- destination`; `MemorySet({1, 2}, 1, 4)` gives `{16843009, 2}`.
---HMPL 3.15 (script process)
---@param destination integer[]|number[]
---@param value integer
---@param byte_num integer
---@return integer
---@return integer[]|number[]
function MemorySet(destination, value, byte_num) end

--- True when the first `byte_num` bytes of the two tables are equal (false past the
--- end of either).
---HMPL 3.16 (script process)
---@param memory_ptr1 integer[]|number[]
---@param memory_ptr2 integer[]|number[]
---@param byte_num integer
---@return boolean
function IsMemoryEqual(memory_ptr1, memory_ptr2, byte_num) end

--- The sine of `x` radians.
---HMPL 4.1 (script process)
---@param x number
---@return number
function sin(x) end

--- The cosine of `x` radians.
---HMPL 4.2 (script process)
---@param x number
---@return number
function cos(x) end

--- The tangent of `x` radians.
---HMPL 4.3 (script process)
---@param x number
---@return number
function tan(x) end

--- The arc sine, -π/2..π/2 (NaN outside -1..1).
---HMPL 4.4 (script process)
---@param x number
---@return number
function asin(x) end

--- The arc cosine, 0..π (NaN outside -1..1).
---HMPL 4.5 (script process)
---@param x number
---@return number
function acos(x) end

--- The arc tangent, -π/2..π/2.
---HMPL 4.6 (script process)
---@param x number
---@return number
function atan(x) end

--- The arc tangent of y/x in the quadrant of (x, y), -π..π.
---HMPL 4.7 (script process)
---@param y number
---@param x number
---@return number
function atan2(y, x) end

--- The absolute value of an integer (a Lua error when it does not fit).
---HMPL 4.8 (script process)
---@param x integer
---@return integer
function abs(x) end

--- The absolute value of a number.
---HMPL 4.9 (script process)
---@param x number
---@return number
function fabs(x) end

--- The smallest integral value not less than `x`, as a float.
---HMPL 4.10 (script process)
---@param x number
---@return number
function ceil(x) end

--- The largest integral value not greater than `x`, as a float.
---HMPL 4.11 (script process)
---@param x number
---@return number
function floor(x) end

--- x·2^y; an overflow gives the largest double (with the sign of the result).
---HMPL 4.12 (script process)
---@param x number
---@param y integer
---@return number
function ldexp(x, y) end

--- e^x; an overflow gives the largest double.
---HMPL 4.13 (script process)
---@param x number
---@return number
function exp(x) end

--- x^y; an overflow gives the largest double (with the sign of the result).
---HMPL 4.14 (script process)
---@param x number
---@param y number
---@return number
function pow(x, y) end

--- The natural logarithm.
---HMPL 4.15 (script process)
---@param x number
---@return number
function log(x) end

--- The base-10 logarithm.
---HMPL 4.16 (script process)
---@param x number
---@return number
function log10(x) end

--- The square root.
---HMPL 4.17 (script process)
---@param x number
---@return number
function sqrt(x) end

--- The cube root.
---HMPL 4.18 (script process)
---@param x number
---@return number
function cbrt(x) end

--- sqrt(x² + y²) without undue overflow.
---HMPL 4.19 (script process)
---@param x number
---@param y number
---@return number
function hypot(x, y) end

--- The variable `hcv_id` (`0xCCIIVVVV`, HMPL 17.1): `value, result` with result 0, or
--- -1 and value 0 for an id luamotion does not have or an axis or group that does
--- not exist (a warning on stderr says which).
---HMPL 17.3.1 (script process)
---@param hcv_id integer
---@return number
---@return integer
function GetConfigVar(hcv_id) end

--- Sets the variable `hcv_id` through the setter it belongs to: 0, the setter's code,
--- 0x0001 for an id luamotion does not have, 0x0003 for a read-only one, 0x0004 for a
--- value the variable cannot hold.
---HMPL 17.3.2 (script process)
---@param hcv_id integer
---@param value number
---@return integer
function SetConfigVar(hcv_id, value) end

--- Adds the axes to the group in order (X, Y, Z, A, B, C; at most 9) and enables it,
--- as AddAxisToGrp for each then EnableGroup. On a failure the axes it added are removed
--- again and the code is returned.
---HMPL 8.3.3 (script process)
---@param group_id integer
---@param ... any
---@return integer
function SetupGroup(group_id, ...) end

--- Writes `num_data` values from the table `input` at `start_idx`. 0 or 0x138F.
---HMPL 11.2 (script process)
---@param start_idx integer
---@param num_data integer
---@param input number[]
---@return integer
function SetUserTable(start_idx, num_data, input) end

--- Reads `num_data` values at `start_idx`: `rc, values`.
---HMPL 11.3 (script process)
---@param start_idx integer
---@param num_data integer
---@return integer
---@return number[]
function GetUserTable(start_idx, num_data) end

--- Writes one value. 0 or 0x138F.
---HMPL 11.4 (script process)
---@param index integer
---@param value number
---@return integer
function SetTableValue(index, value) end

--- Reads one value.
---HMPL 11.5 (script process)
---@param index integer
---@return number
function GetTableValue(index) end

--- Saves a range to the controller's disk: the file is replaced whole or not at all.
--- 0, 0x138F or 0x0139.
---HMPL 11.6 (script process)
---@param start_idx integer
---@param num_data integer
---@return integer
function SaveUserTable(start_idx, num_data) end

--- Loads a range from the controller's disk. 0, 0x138F or 0x0138 (nothing saved).
---HMPL 11.7 (script process)
---@param start_idx integer
---@param num_data integer
---@return integer
function LoadUserTable(start_idx, num_data) end

--- Assembles a FUN147 step table (`001 SPD 5000`, `LIN ADR,500,400,,,Ut`, `WAIT TIME,100`,
--- `GOTO NEXT`, `MEND`, `;` comments) and writes it at `sr` (0xA55C, N, 15 words a
--- step). A text error is a Lua error with its line and column; nothing is written then.
---Fatek FUN147 (script process)
---@param sr string
---@param text string
---@return integer
function MHSPOLoad(sr, text) end

--- The step table at `sr` as text; a Lua error naming the FUN147 code (34, 35, 36, …)
--- when `sr` holds no valid table.
---Fatek FUN147 (script process)
---@param sr string
---@return string
function MHSPOText(sr) end

--- A register: "R1000", "D4062" the 16-bit word 0..65535; "DR1000", "DD100" the signed
--- 32-bit value of n (low word) and n+1 (high word). A Lua error for an address that
--- does not exist.
---Fatek FUN147 (script process)
---@param addr string
---@return integer
function GetPlcReg(addr) end

--- Writes a register: a word 0..65535 (or -32768..-1 as its two's complement), a double
--- word (DR, DD) -2^31..2^31-1. 0; a Lua error for an address or value that does not fit.
---Fatek FUN147 (script process)
---@param addr string
---@param value integer
---@return integer
function SetPlcReg(addr, value) end

--- A relay: "X0"-"X255", "Y0"-"Y255", "M0"-"M2001", "S0"-"S999".
---Fatek FUN147 (script process)
---@param addr string
---@return boolean
function GetPlcRelay(addr) end

--- Writes a relay (X too: the simulation has no input terminals). 0.
---Fatek FUN147 (script process)
---@param addr string
---@param on boolean|number
---@return integer
function SetPlcRelay(addr, on) end

FreePort = {}
FreePort.Eth = {}
--- Listens on TCP `Port` (3000..10000) as session `SessionID`; one peer at a time, the
--- next one is accepted when the last has gone. Listens on 127.0.0.1 unless the
--- machine file's `[freeport] bind` names another address. 0 or 1, 3, 4, 8. The codes of all
--- `FreePort.Eth` functions: 0 ok, 1 bad argument, 2 no such session, 3 session id in
--- use, 4 open failed, 5 not connected, 6 frame too long, 7 send failed, 8 too many
--- sessions (32 a task).
---DXMC 8.3 FreePort (script process)
---@param SessionID integer
---@param Port integer
---@param SByte any
---@param EByte any
---@return integer
function FreePort.Eth.OpenAsServer(SessionID, Port, SByte, EByte) end

--- Connects to `IPAddr`:`Port` (3000..10000) as session `SessionID`, waiting at most 1 s.
--- 0 or 1, 3, 4, 8.
---DXMC 8.3 FreePort (script process)
---@param SessionID integer
---@param IPAddr string
---@param Port integer
---@param SByte any
---@param EByte any
---@return integer
function FreePort.Eth.OpenAsClient(SessionID, IPAddr, Port, SByte, EByte) end

--- Sends `Msg` as one frame: a string as its bytes, a number as its Lua text, a boolean
--- as `true`/`false`, a table as its bytes 0..255. `code, Msg`: 0 or 1 (nil, a table
--- not of bytes), 2, 5, 6 (more than 1024 bytes), 7.
---DXMC 8.3 FreePort (script process)
---@param SessionID integer
---@param Msg any
---@return integer
---@return any
function FreePort.Eth.Tx(SessionID, Msg) end

--- The next received frame without its start and end bytes, never waiting:
--- `code, data, count`; `0, "", 0` when no frame is complete. 6 for a frame longer than
--- 1024 bytes (dropped), 5 when no peer is connected and nothing is left, 2.
---DXMC 8.3 FreePort (script process)
---@param SessionID integer
---@return integer
---@return string
---@return integer
function FreePort.Eth.Rx(SessionID) end

--- Closes the session and frees its port. 0 or 2.
---DXMC 8.3 FreePort (script process)
---@param SessionID integer
---@return integer
function FreePort.Eth.Close(SessionID) end

--- Closes every session of the task. 0.
---DXMC 8.3 FreePort (script process)
---@return integer
function FreePort.Eth.CloseAll() end

--- Drops what was received and not yet read. 0 or 2.
---DXMC 8.3 FreePort (script process)
---@param SessionID integer
---@return integer
function FreePort.Eth.BuffClear(SessionID) end

--- `0, ids`: the sessions of the task, ascending.
---DXMC 8.3 FreePort (script process)
---@return integer
---@return number[]
function FreePort.Eth.GetSessions() end

--- 0 while a peer is connected, 5 when none is (yet), 2 for no such session.
---DXMC 8.3 FreePort (script process)
---@param SessionID integer
---@return integer
function FreePort.Eth.ConnectCheck(SessionID) end

--- Starts the User ASCII agent: the task's process listens on the User ASCII port
--- (`[ascii] user_port`, 4000) and hands every line a client sends to
--- `parser(command)`; the string it returns goes back as a line (nil: an empty line; an
--- error: `ERROR <message>`, and the agent lives on). Lines are served while the task
--- waits (Sleep, Till, DELAY) and, once the program has returned, until the task is
--- stopped. One agent controller-wide: 0, or 0x1392 while another task's agent runs;
--- calling it again from the same task changes the parser.
---HMPL 22.2.1 (script process)
---@param parser fun(): any
---@return integer
function START_ASCII_AGENT(parser) end

--- Sends `message` (its first `length` bytes; all of it when `length` is nil) as a line
--- to every client of the User ASCII agent. 0; 0x138D for more than 128 bytes; 0x1452
--- when no agent runs.
---HMPL 22.2.2 (script process)
---@param message string
---@param length integer
---@return integer
function ASCII_ServerBroadcast(message, length) end

FreePort.Serial = {}
--- Switches port 1 to FreePort with these delimiters and `Protocol` (a FreePort code of
--- parameter 5-1: 0x09..0x0E, 0x10, 0x12, 0x14, 0x17, 0x1A, 0x1D; omitted: the line's
--- frame as it is) and clears the receive buffer: `code, P309`, the FreePort format
--- word of parameter 5-5 (DCBAUZYX; `Init(1, ":", ";")` gives 0x00113B3A). 0 or 1, 9, 10.
---DXMC 8.3 FreePort (script process)
---@param port integer
---@param SrtByte any
---@param EndByte any
---@param Protocol any
---@return integer
---@return integer
function FreePort.Serial.Init(port, SrtByte, EndByte, Protocol) end

--- Sends `Msg` as one frame (converted as `FreePort.Eth.Tx` does): `code, Msg`. 0 or 1,
--- 6 (more than 256 bytes), 9, 10, 13.
---DXMC 8.3 FreePort (script process)
---@param port integer
---@param Msg any
---@return integer
---@return any
function FreePort.Serial.Tx(port, Msg) end

--- The next received frame without its start and end bytes, never waiting:
--- `code, data, count`; `0, "", 0` when none is complete. 6 for a frame longer than 256
--- bytes (dropped), 9, 10, 11, 12, 13.
---DXMC 8.3 FreePort (script process)
---@param port integer
---@return integer
---@return string
---@return integer
function FreePort.Serial.Rx(port) end

--- Connects to an ASCII server (`ip` an IP address, `port` a string): `rc, socket_id`.
--- 0x17D5 failed (refused, bad address, 8 sockets open), 0x17D4 timeout.
---HMPL 22.2.3 (script process)
---@param ip string
---@param port string
---@return integer
---@return integer
function ASCII_ClientConnect(ip, port) end

--- Receives what has arrived, up to `length` (1..512) bytes, waiting for the first:
--- `rc, text`. 0x17DF failed (closed by the server, unknown socket, bad length),
--- 0x17DE timeout.
---HMPL 22.2.4 (script process)
---@param socket_id integer
---@param length integer
---@return integer
---@return string
function ASCII_ClientRecv(socket_id, length) end

--- Sends the first `length` (0..512) bytes of `buffer` (fewer if it is shorter).
--- 0x17E9 failed, 0x17E8 timeout.
---HMPL 22.2.5 (script process)
---@param socket_id integer
---@param length integer
---@param buffer string
---@return integer
function ASCII_ClientSend(socket_id, length, buffer) end

--- Closes the connection. 0x17D8 timeout, 0x138F unknown socket.
---HMPL 22.2.6 (script process)
---@param socket_id integer
---@return integer
function ASCII_ClientDisconnect(socket_id) end

--- Connects to a Modbus TCP server at `ip` (port 502, or `"ip:port"`): `rc, socket_id`.
--- 0x1839 failed (refused, bad address, 8 sockets open), 0x1838 timeout.
---HMPL 22.3.1 (script process)
---@param ip string
---@return integer
---@return integer
function Modbus_ClientConnect(ip) end

--- Closes the connection. 0x183C timeout, 0x138F unknown socket.
---HMPL 22.3.2 (script process)
---@param socket_id integer
---@return integer
function Modbus_ClientDisconnect(socket_id) end

--- FC 03, 1..125 registers: `rc, bytes, use_length` (each register high byte first).
--- 0x183D count out of range, 0x1840 failed (exception reply, lost connection),
--- 0x183F timeout.
---HMPL 22.3.3 (script process)
---@param socket_id integer
---@param start_addr integer
---@param num_regs integer
---@return integer
---@return integer[]
---@return integer
function Modbus_ClientRead_HoldReg(socket_id, start_addr, num_regs) end

--- FC 04, 1..125 input registers, as `Modbus_ClientRead_HoldReg`.
---HMPL 22.3.4 (script process)
---@param socket_id integer
---@param start_addr integer
---@param num_regs integer
---@return integer
---@return integer[]
---@return integer
function Modbus_ClientRead_InputReg(socket_id, start_addr, num_regs) end

--- FC 01, 1..2000 coils: `rc, bytes, use_length`, eight a byte, the first in bit 0.
---HMPL 22.3.5 (script process)
---@param socket_id integer
---@param start_addr integer
---@param num_coils integer
---@return integer
---@return integer[]
---@return integer
function Modbus_ClientRead_Coils(socket_id, start_addr, num_coils) end

--- FC 02, 1..2000 discrete inputs, as `Modbus_ClientRead_Coils`.
---HMPL 22.3.6 (script process)
---@param socket_id integer
---@param start_addr integer
---@param num_inputs integer
---@return integer
---@return integer[]
---@return integer
function Modbus_ClientRead_Inputs(socket_id, start_addr, num_inputs) end

--- FC 16, 1..123 registers from the table `write_data` (integers 0..65535): `rc, bytes,
--- use_length`, the reply's start address and count. 0x183D for a count out of range or
--- a short or bad table.
---HMPL 22.3.7 (script process)
---@param socket_id integer
---@param start_addr integer
---@param num_regs integer
---@param write_data number[]
---@return integer
---@return integer[]
---@return integer
function Modbus_ClientWrite_HoldReg(socket_id, start_addr, num_regs, write_data) end

--- FC 15, 1..1968 coils: coil i is bit i % 16 of `write_data[i / 16 + 1]` (`{15}` sets
--- four), otherwise as `Modbus_ClientWrite_HoldReg`.
---HMPL 22.3.8 (script process)
---@param socket_id integer
---@param start_addr integer
---@param num_coils integer
---@param write_data number[]
---@return integer
---@return integer[]
---@return integer
function Modbus_ClientWrite_Coils(socket_id, start_addr, num_coils, write_data) end

--- Expects `actual == expected` as Lua compares them (3 equals 3.0; a table only itself).
---luamotion test (script process)
---@param actual any
---@param expected any
---@param message string
---@return boolean
function expect_eq(actual, expected, message) end

--- Expects `|actual - expected| <= tolerance` (a NaN never is): `expect_near(GetPosFb(0), 100, 1e-3)`.
---luamotion test (script process)
---@param actual number
---@param expected number
---@param tolerance number
---@param message string
---@return boolean
function expect_near(actual, expected, tolerance, message) end

--- Expects a true value (not false, nil or 0, as `Till` reads a condition).
---luamotion test (script process)
---@param value any
---@param message string
---@return boolean
function expect_true(value, message) end

PI = 3.141592653589793 -- HMPL 23.1
SQRT2 = 1.4142135623730951 -- HMPL 23.1
SQRT1_2 = 0.7071067811865476 -- HMPL 23.1
TRUE = 1 -- HMPL 1.4
FALSE = 0 -- HMPL 1.4
HMPL_STR_MAX_LEN = 512 -- HMPL 3.1
CR_LF = "\r\n" -- DXMC 8.3 DRL
HMPL_SLOT_1 = 65536 -- HMPL 9.1 (value: luamotion)
HMPL_SLOT_2 = 131072 -- HMPL 9.1 (value: luamotion)
HMPL_SLOT_3 = 196608 -- HMPL 9.1 (value: luamotion)
HMPL_SLOT_4 = 262144 -- HMPL 9.1 (value: luamotion)
BM_BUFF = 0 -- HMPL table 8.1.4.1 (value: luamotion)
BM_ABORT = 1 -- HMPL table 8.1.4.1 (value: luamotion)
BM_LOW = 2 -- HMPL table 8.1.4.1 (value: luamotion)
BM_PREV = 3 -- HMPL table 8.1.4.1 (value: luamotion)
BM_NEXT = 4 -- HMPL table 8.1.4.1 (value: luamotion)
BM_HIGH = 5 -- HMPL table 8.1.4.1 (value: luamotion)
BM_LOOKAHEAD = 6 -- HMPL table 8.1.4.1 (value: luamotion)
TM_NONE = 0 -- HMPL table 8.1.5.1 (value: luamotion)
TM_CONST_VEL = 1 -- HMPL table 8.1.5.1 (value: luamotion)
TM_CORNER_DIST = 2 -- HMPL table 8.1.5.1 (value: luamotion)
TM_MAX_CORNER_DEV = 3 -- HMPL table 8.1.5.1 (value: luamotion)
TM_MAX_CORNER_CURV = 4 -- HMPL table 8.1.5.1 (value: luamotion)
TM_START_VEL = 5 -- HMPL table 8.1.5.1, not available (value: luamotion)
CS_MCS = 1 -- HMPL table 8.1.2.1 (value: luamotion)
CS_PCS = 2 -- HMPL table 8.1.2.1 (value: luamotion)
CS_OFFSET = 4 -- HMPL table 8.1.2.1 (value: luamotion)
CS_GLOBAL = 8 -- HMPL table 8.1.2.1, not supported (value: luamotion)
CS_ACS = 16 -- HMPL table 8.1.2.1 (value: luamotion)
SHAPER_NORMAL = 1 -- HMPL 15.7
SHAPER_ROBUST = 0 -- HMPL 15.7
HMPL_DAC_NONE = 0 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_N10_P10 = 1 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_P0_P10 = 2 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_N5_P5 = 3 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_P0_P5 = 4 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_P0_P20 = 5 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_P4_P20 = 6 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_N20_P20 = 7 -- HMPL table 10.1.1 (value: luamotion)
HMPL_DAC_SIGNED = 256 -- HMPL table 10.1.1 (value: luamotion)
HMPL_REF_POS = 256 -- HMPL 10.4.1 (value: luamotion)
HMPL_REF_VEL = 512 -- HMPL 10.4.1 (value: luamotion)
HMPL_REF_ACC = 768 -- HMPL 10.4.1 (value: luamotion)
HMPL_POS_FB = 1024 -- HMPL 10.4.1 (value: luamotion)
HMPL_VEL_FB = 1280 -- HMPL 10.4.1 (value: luamotion)
HMPL_ACC_FB = 1536 -- HMPL 10.4.1 (value: luamotion)
HMPL_CUR_FB = 1792 -- HMPL 10.4.1 (value: luamotion)
HOME_METHOD_1 = 1
HOME_METHOD_2 = 2
HOME_METHOD_7 = 7
HOME_METHOD_8 = 8
HOME_METHOD_9 = 9
HOME_METHOD_10 = 10
HOME_METHOD_11 = 11
HOME_METHOD_12 = 12
HOME_METHOD_13 = 13
HOME_METHOD_14 = 14
HOME_METHOD_17 = 17
HOME_METHOD_18 = 18
HOME_METHOD_23 = 23
HOME_METHOD_24 = 24
HOME_METHOD_25 = 25
HOME_METHOD_26 = 26
HOME_METHOD_27 = 27
HOME_METHOD_28 = 28
HOME_METHOD_29 = 29
HOME_METHOD_30 = 30
HOME_METHOD_33 = 33
HOME_METHOD_34 = 34
HOME_METHOD_37 = 37
HMPL_AXIS_0 = 0
HMPL_AXIS_1 = 1
HMPL_AXIS_2 = 2
HMPL_AXIS_3 = 3
HMPL_AXIS_4 = 4
HMPL_AXIS_5 = 5
HMPL_AXIS_6 = 6
HMPL_AXIS_7 = 7
HMPL_AXIS_8 = 8
HMPL_AXIS_9 = 9
HMPL_AXIS_10 = 10
HMPL_AXIS_11 = 11
HMPL_AXIS_12 = 12
HMPL_AXIS_13 = 13
HMPL_AXIS_14 = 14
HMPL_AXIS_15 = 15
CS_WCS1 = 256
CS_WCS2 = 512
CS_WCS3 = 768
CS_WCS4 = 1024
CS_WCS5 = 1280
CS_WCS6 = 1536
CS_WCS7 = 1792
CS_WCS8 = 2048
CS_WCS9 = 2304
CS_WCS10 = 2560
CS_WCS11 = 2816
CS_WCS12 = 3072
CS_WCS13 = 3328
CS_WCS14 = 3584
CS_WCS15 = 3840
eERR_HCV_ID_NOT_FOUND = 0x0001
eERR_DATA_EXCEEDED = 0x0002
eERR_HCV_IS_READ_ONLY = 0x0003
eERR_HCV_VALUE_OUT_OF_RANGE = 0x0004
eERR_EWM_CALLBACK_BUSY = 0x0050
eERR_EMERGENCY_STOP = 0x0064
eERR_NOT_VALID_TASKID = 0x0107
eERR_TASK_IS_RUNNING = 0x0108
eERR_FUNC_NOT_IN_TASK = 0x0109
eERR_TASK_EMPTY = 0x010A
eERR_TASK_NOT_RUNNING = 0x010B
eERR_NIC_INIT_TOUT = 0x012C
eERR_HARDWARE_MISMATCH = 0x012D
eERR_SLAVE_NUM_MISMATCH = 0x012E
eERR_INVALID_MCK_CNFG = 0x0130
eERR_HIMC_LOAD_CONFIG_FAIL = 0x0138
eERR_HIMC_SAVE_CONFIG_FAIL = 0x0139
eERR_HIMC_SAVE_CONFIG_COPY_FAIL = 0x013A
eERR_ETHERCAT_LICENSE_MISMATCH = 0x013C
eERR_ISR_NOT_STABLE = 0x01F4
eWRN_ISR_NOT_STABLE = 0x41F4
eERR_MCK_OVERLOAD = 0x01F5
eDBG_MCK_OVERLOAD = 0xC1F5
eERR_ISR_OVERLOAD = 0x01F6
eDBG_ISR_OVERLOAD = 0xC1F6
eERR_HMPL_INVALID_ARG = 0x1388
eERR_HMPL_INVALID_PTR = 0x1389
eERR_HMPL_STACK_OVERFLOW = 0x138A
eERR_HMPL_ILLEGAL_MEM_OP = 0x138B
eERR_HMPL_MOTION_NOT_READY = 0x138C
eERR_HMPL_STR_TOO_LONG = 0x138D
eERR_HMPL_INVALID_STR_FORMAT = 0x138E
eERR_HMPL_ARG_OUT_OF_RANGE = 0x138F
eERR_HMPL_ASCII_AGENT_RUNNING = 0x1392
eERR_HMPL_CANNOT_RUN_IN_DEBUG = 0x139C
eERR_HMPL_TOO_MANY_BRK_POINT = 0x13A6
eERR_HMPL_MUTEX_LOCK_TWICE = 0x13EC
eERR_HMPL_INVALID_SYS_TIME_MEMORY = 0x1450
eERR_HMPL_NOT_SUPPORTED = 0x1451
eERR_HMPL_CLIENT_NOT_CONNECTED = 0x1452
eERR_HMPL_NOT_IN_OP_MODE = 0x14B4
eERR_HMPL_INTERNAL_ERROR = 0x176F
eERR_HMPL_EXEC_FAILED = 0x1770
eERR_HMPL_ASM_LOAD_FAILED = 0x1771
eERR_HMPL_STARTTASK_TIMEOUT = 0x1772
eERR_HMPL_STOPTASK_TIMEOUT = 0x1773
eERR_ASCII_CONNECT_TIMEOUT = 0x17D4
eERR_ASCII_CONNECT_FAILED = 0x17D5
eERR_ASCII_MULTI_CONNECTING = 0x17D6
eERR_ASCII_MULTI_DISCONNECTING = 0x17D7
eERR_ASCII_DISCONNECT_TIMEOUT = 0x17D8
eERR_ASCII_RECV_TIMEOUT = 0x17DE
eERR_ASCII_RECV_FAIL = 0x17DF
eERR_ASCII_MULTI_RECVING = 0x17E0
eERR_ASCII_SEND_TIMEOUT = 0x17E8
eERR_ASCII_SEND_FAIL = 0x17E9
eERR_ASCII_MULTI_SENDING = 0x17EA
eERR_MODBUS_CONNECT_TIMEOUT = 0x1838
eERR_MODBUS_CONNECT_FAILED = 0x1839
eERR_MODBUS_MULTI_CONNECTING = 0x183A
eERR_MODBUS_MULTI_DISCONNECTING = 0x183B
eERR_MODBUS_DISCONNECT_TIMEOUT = 0x183C
eERR_MODBUS_DATALENGTH_ERR = 0x183D
eERR_MODBUS_SOCKET_BUSY = 0x183E
eERR_MODBUS_JOB_TIMEOUT = 0x183F
eERR_MODBUS_JOB_FAIL = 0x1840
eMSG_HIMC_SET_DEFAULT = 0xB037
eMSG_HIMC_REBOOT = 0xB038
eMSG_HIMC_BOOT = 0xB039
eMSG_HIMC_INFO = 0xB03A
eMSG_HIMC_STORE_CONFIG = 0xB03B
eMSG_API_MAIN_ID_CHANGE_GET = 0xB03E
eMSG_API_MAIN_ID_CHANGE_RELEASE = 0xB03F
eMSG_START_HMI_SCOPE = 0xB2C8
eMSG_STOP_HMI_SCOPE = 0xB2C9
eERR_SYS_LOG = 0x3FFF
eWRN_SYS_LOG = 0x7FFF
eMSG_SYS_LOG = 0xBFFF
eDBG_SYS_LOG = 0xFFFF
eERR_AXIS_CMD_UNKOWN = 0x000A
eERR_AXIS_CMD_QUEUE_FULL = 0x001E
eERR_AXIS_CMD_INVALID_IN_SIM = 0x0050
eERR_AXIS_CMD_INVALID_IN_VIRTUAL = 0x0060
eERR_AXIS_CMD_INVALID_STATE = 0x0064
eERR_AXIS_CMD_INVALID_ENABLED = 0x006E
eERR_AXIS_CMD_INVALID_DISABLED = 0x0078
eERR_AXIS_CMD_INVALID_MOVING = 0x0082
eERR_AXIS_CMD_INVALID_STOPPING = 0x008C
eERR_AXIS_CMD_INVALID_ERROR_STATE = 0x0096
eERR_AXIS_CMD_INVALID_IN_SYNC = 0x00A0
eERR_AXIS_CMD_INVALID_GEAR_MASTER = 0x00AA
eERR_AXIS_CMD_INVALID_PP_MODE = 0x00B4
eERR_AXIS_CMD_INVALID_MAP_SWITCHING = 0x00BE
eERR_AXIS_CMD_INVALID_INPUTSHAPING_ENABLED = 0x00C8
eERR_AXIS_CMD_INVALID_COMP_ENABLED = 0x00D2
eERR_AXIS_CMD_INVALID_GANTRY_MODE = 0x00DC
eERR_AXIS_CMD_INVALID_GROUPED = 0x00E6
eERR_AXIS_CMD_INVALID_CONTROL_MODE = 0x00F0
eERR_AXIS_CMD_INVALID_OP_MODE = 0x00FA
eERR_AXIS_CMD_INVALID_BUFFER_MODE = 0x0104
eERR_AXIS_CMD_INVALID_SETBUFFERMODE = 0x0105
eERR_AXIS_CMD_INVALID_TP_ENABLED = 0x010E
eERR_AXIS_CMD_INVALID_PARAMETER = 0x012C
eERR_AXIS_CMD_INVALID_POS = 0x0136
eERR_AXIS_CMD_INVALID_VEL = 0x0140
eERR_AXIS_CMD_INVALID_ACC = 0x014A
eERR_AXIS_CMD_INVALID_DEC = 0x0154
eERR_AXIS_CMD_INVALID_JERK = 0x015E
eERR_AXIS_CMD_INVALID_SM_TIME = 0x0168
eERR_AXIS_CMD_INVALID_KILL_DEC = 0x0172
eERR_AXIS_CMD_INVALID_VEL_SCALE = 0x017C
eERR_AXIS_COMP_NOT_CNFG = 0x0190
eERR_AXIS_CMD_INVALID_MASTER_SLAVE_CONNECTION = 0x01C2
eERR_AXIS_CMD_INVALID_SLAVE_ID = 0x01CC
eERR_AXIS_CMD_INVALID_GEAR_RATIO = 0x01D6
eERR_AXIS_CMD_INVALID_ROLLOVER_POS = 0x01F4
eERR_AXIS_CMD_INVALID_ROLLOVER_PP_MODE = 0x01FE
eERR_AXIS_CMD_INVALID_FORCECONST_TRQMODE = 0x0208
eERR_AXIS_CMD_INVALID_NO_SPECIFIC_PDO = 0x0258
eERR_AXIS_DRIVE_FAULT = 0x03F2
eERR_AXIS_DRIVE_ABNORMAL_DISABLE = 0x03FC
eERR_AXIS_DRIVE_ENABLE_TOUT = 0x0406
eERR_AXIS_DRIVE_ENABLE_TOUT_RMT = 0x0407
eERR_AXIS_DRIVE_CLEAR_ERROR_TOUT = 0x0410
eERR_AXIS_DRIVE_DISABLE_TOUT = 0x041A
eERR_AXIS_DRIVE_HOME_TOUT = 0x0424
eERR_AXIS_DRIVE_HOME_FAILED = 0x042E
eERR_AXIS_VEL_LIMIT = 0x0456
eWRN_AXIS_VEL_LIMIT = 0x4456
eERR_AXIS_ACC_LIMIT = 0x0460
eERR_AXIS_CURR_LIMIT = 0x046A
eERR_AXIS_DAMPINGRATIO_LIMIT = 0x0474
eERR_AXIS_FREQUENCY_LIMIT = 0x047E
eERR_AXIS_SWRL = 0x07DA
eERR_AXIS_SWLL = 0x07E4
eERR_AXIS_HWRL = 0x07EE
eERR_AXIS_HWLL = 0x07F8
eERR_AXIS_COMP_LIMIT = 0x0802
eERR_AXIS_PERR = 0x083E
eERR_AXIS_VERR = 0x0848
eERR_AXIS_PVT_MOTION_VEL_LIMIT = 0x08A2
eERR_AXIS_PVT_MOTION_ACC_LIMIT = 0x08AC
eERR_AXIS_PVT_MOTION_INVALID_TIME = 0x08B6
eERR_AXIS_CTRL_ERR = 0x0BB8
eERR_AXIS_CMD_GEAR_DISABLED = 0x0FA0
eERR_AXIS_CMD_INVALID_AXIS_IN_CAM = 0x0FA1
eERR_CAM_CMD_INVALID_ENGAGE_WINDOW = 0x1388
eERR_CAM_CMD_INVALID_ENGAGE_POSITION = 0x1389
eERR_CAM_CMD_INVALID_MASTER_SCALE_FACTOR = 0x138A
eERR_CAM_CMD_INVALID_CAM_SCALE_FACTOR = 0x138B
eERR_CAM_CMD_INVALID_CAMTABLE_ID = 0x138C
eERR_CAM_CMD_INVALID_DISENGAGE_WINDOW = 0x138D
eERR_CAM_CMD_INVALID_DISENGAGE_POSITION = 0x138E
eERR_CAM_CMD_INVALID_OPERATION_IN_ENGAGED_STATE = 0x138F
eERR_CAM_CMD_INVALID_START_MODE = 0x1390
eERR_CAM_CMD_INVALID_MOVE_MODE = 0x1391
eERR_CAM_ENGAGED_FAILED = 0x1392
eERR_CAM_CMD_NOTINUSE = 0x1393
eERR_CAM_CMD_CAM_DISABLED = 0x1394
eERR_CAM_CMD_INVALID_AXIS_NOT_INCAM = 0x1395
eERR_CAM_CMD_INVALID_AXIS_NOT_IN_DISENGAGED = 0x1396
eERR_CAM_CMD_INVALID_AXIS_IN_GEAR = 0x1397
eERR_CRD_CMD_UNKNOWN = 0x000A
eERR_CRD_CMD_REACH_MAX_NUM_AXIS = 0x0014
eERR_CRD_CMD_INVALID_KIN_SETTING = 0x001E
eERR_CRD_CMD_INVALID_SPECIFIC_KIN = 0x001F
eERR_CRD_CMD_AXIS_DUPLICATED = 0x0028
eERR_CRD_CMD_GRP_SIZE_EMPTY = 0x0032
eERR_CRD_CMD_GRP_SIZE_FULL = 0x003C
eERR_CRD_CMD_INVALID_MOVING = 0x0046
eERR_CRD_CMD_INVALID_DISABLED = 0x0050
eERR_CRD_CMD_INVALID_INPUTSHAPING_PARAMETER_INCOMPLETE = 0x005A
eERR_CRD_CMD_INVALID_STATE = 0x006E
eERR_CRD_CMD_QUEUE_FULL = 0x0078
eERR_CRD_CMD_GRP_AXIS_INVALID = 0x0082
eERR_CRD_CMD_QUEUE_IS_NOT_EMPTY = 0x008C
eERR_CRD_CMD_INVALID_QUEUE_SIZE = 0x0096
eERR_CRD_CMD_INVALID_POS = 0x00D2
eERR_CRD_CMD_INVALID_LIN_VEL = 0x00DC
eERR_CRD_CMD_INVALID_LIN_ACC = 0x00E6
eERR_CRD_CMD_INVALID_LIN_DEC = 0x00F0
eERR_CRD_CMD_INVALID_LIN_JERK = 0x00FA
eERR_CRD_CMD_INVALID_LIN_SM_TIME = 0x0104
eERR_CRD_CMD_INVALID_DAMPINGRATIO = 0x010E
eERR_CRD_CMD_INVALID_FREQUENCY = 0x0118
eERR_CRD_CMD_INVALID_ANG_VEL = 0x0140
eERR_CRD_CMD_INVALID_ANG_ACC = 0x014A
eERR_CRD_CMD_INVALID_ANG_DEC = 0x0154
eERR_CRD_CMD_INVALID_ANG_JERK = 0x015E
eERR_CRD_CMD_INVALID_ANG_SM_TIME = 0x0168
eERR_CRD_CMD_INVALID_VEL_SCALE = 0x0190
eERR_CRD_CMD_INVALID_TRANS_VEL = 0x019A
eERR_CRD_CMD_INVALID_TRANS_DIS = 0x01A4
eERR_CRD_CMD_INVALID_TRANS_DEV = 0x01A5
eERR_CRD_CMD_INVALID_TRANS_CURVE = 0x01A6
eERR_CRD_CMD_TRANS_MODE_UNKNOWN = 0x01B8
eERR_CRD_CMD_COORD_SYS_UNKNOWN = 0x01C2
eERR_CRD_CMD_BLEND_MODE_UNKNOWN = 0x01CC
eERR_CRD_CMD_LIN_INVALID_PARAM = 0x01FE
eERR_CRD_CMD_CIRC_INVALID_PARAM = 0x0262
eERR_CRD_CMD_CIRC_INVALID_CENTER = 0x026C
eERR_CRD_CMD_CIRC_ANGLE_SMALL = 0x0276
eERR_CRD_CMD_CIRC_INVALID_RADIUS = 0x0280
eERR_CRD_CMD_CIRC_INVALID_COORD = 0x028A
eERR_CRD_CMD_BEZIER_INVALID_PARAM = 0x02C6
eERR_CRD_CMD_BSPLINE_INVALID_PARAM = 0x02D0
eERR_CRD_CMD_CURVE_INVALID_STARTPOS = 0x02DA
eERR_CRD_CMD_COORD_INVALID_PARAM = 0x02E4
eERR_CRD_CMD_NURBS_INVALID_PARAM = 0x02EE
eERR_CRD_CMD_LOOKAHEAD_INVALID_PARAM = 0x02F8
eERR_CRD_AXIS_ABNORMALLY_DISABLED = 0x03F2
eERR_CRD_AXIS_SWL = 0x03FC
---@type integer
system_fclk = nil -- controller cycles since start (read-only) (HMPL 23.2)
---@type integer
system_timeInMs = nil -- controller time, ms (read-only) (HMPL 23.2)
---@type number[]
system_user_table = nil -- the user table, indices 0..511999, shared by all tasks (HMPL 11, 23.2)
---@type integer
system_ltest0 = nil -- system_ltest0 .. system_ltest9: integers shared by all tasks (HMPL 23.2)
---@type number
system_dtest0 = nil -- system_dtest0 .. system_dtest9: numbers shared by all tasks (HMPL 23.2)
---@type number[]
system_mtest = nil -- 10 numbers shared by all tasks, indices 0..9 (HMPL 23.2)
---@type integer
_TASKID_ = nil -- this task's id (HMPL 19.1)
---@type table<string, number|boolean|string>
task_vars = nil -- this task's variables: they keep their values when the task is stopped and started again (64 per task, names up to 31 bytes, strings up to 64) (HMPL 1.5 (luamotion))
---@type table<integer, boolean>
HIMC_GPI = nil -- controller input i (1..8) as a boolean: `HIMC_GPI[4]` or `HIMC_GPI(4)` (read-only; a Lua error for no such input) (HMPL 19.4)
---@type table<integer, boolean>
HIMC_GPO = nil -- controller output i (1..8): read as `HIMC_GPO[1]` or `HIMC_GPO(1)`, set with `HIMC_GPO[1] = HIMC_GPI[4] and HIMC_GPI[6]` (true, false or a number, 0 is off) (HMPL 19.5)
