//! Axis groups (HMPL ch. 8): up to 9 axes that move together along a path. A group owns
//! its settings, its interpolator (`path::planner`: queue, feed, junctions, look-ahead) and
//! a moving average over its smooth time (the S-curve, as an axis' smoothing, HMPL 5.1)
//! taken along the path (`path::smoothing`), so that it keeps the path's blends and
//! curves. With Cartesian kinematics (table 8.1.3.1, the only one available) the i-th axis
//! added is the i-th MCS coordinate X, Y, Z, A, B, C.
//!
//! The group's states (HMPL 3.3, 8.2): `Disabled` (axes grouped, each on its own
//! generator), `Standby` (enabled: the interpolator gives the axes' references, moving or
//! not), `ErrorStop` (an axis faulted or hit a limit: the axes left sync and came to rest
//! on their own; `ResetGroup` once the causes are gone).

mod commands;
pub mod motion;
pub mod settings;
mod vibration;

use api::{ErrorCode, GroupError};
use path::Pose;
use path::blend::{TransitionMode, TransitionParams};
use path::frames::{CoordSys, Frames};
use path::planner::{Limits, Planner};
use path::sample::Sample;
use path::smoothing::PathSmoother;
use schema::{GroupSnapshot, MAX_GROUP_AXES, fault_status, group_fault_status, group_motion_status};

use crate::shaping::{GROUP_MIN_SHAPER_HZ, InputShaper};
use devices::profile::Kinematics;
use settings::{GroupSettings, KIN_CARTESIAN, MAX_SMOOTH_MS};

/// MCS coordinates: X, Y, Z, A, B, C (HMPL 8.1.2).
pub const COORDINATES: usize = 6;

/// A group's state (HMPL 3.3, 8.2; see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GroupState {
    /// Not enabled: each grouped axis runs on its own generator.
    Disabled,
    /// Enabled: the interpolator gives the axes' references, moving or not.
    Standby,
    /// An axis faulted or hit a limit; the axes left sync until ResetGroup.
    ErrorStop,
}

/// One axis group (HMPL ch. 8): its axes, settings, interpolator and the smoothing and
/// shaping after it.
pub struct Group {
    axes: [u8; MAX_GROUP_AXES],
    count: usize,
    state: GroupState,
    settings: GroupSettings,
    kin: i64,
    /// The coordinate system of later targets and the group's transforms (HMPL 8.1.2).
    coord_sys: CoordSys,
    frames: Frames,
    /// The transition of later junctions (HMPL 8.3.25, 8.3.26).
    trans_mode: TransitionMode,
    trans: TransitionParams,
    planner: Planner,
    /// The S-curve: a moving average over the smooth time, along the path.
    smoother: PathSmoother,
    /// HMPL 15.8-15.10: input shaping after the smoothing, on each coordinate.
    shapers: [InputShaper; COORDINATES],
    period_s: f64,
    /// The last cycle's interpolator output and the smoothed pose the axes took.
    sample: Sample,
    pose_cmd: Kinematics6,
    /// `grp_fault_status` bits other than ErrorStop (table 8.1.1.4).
    faults: u32,
    /// The task whose command set the present motion going (fault reactions, 0x001F).
    commander: Option<u8>,
}

/// A pose with its velocity and acceleration, per coordinate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Kinematics6 {
    pub pos: Pose,
    pub vel: Pose,
    pub acc: Pose,
}

impl Group {
    pub(crate) fn new(period_s: f64) -> Self {
        let max_samples = (MAX_SMOOTH_MS / 1000.0 / period_s).round() as usize + 1;
        Group {
            axes: [0; MAX_GROUP_AXES],
            count: 0,
            state: GroupState::Disabled,
            settings: GroupSettings::default(),
            kin: KIN_CARTESIAN,
            coord_sys: CoordSys::MCS,
            frames: Frames::default(),
            trans_mode: TransitionMode::None,
            trans: TransitionParams::default(),
            planner: Planner::new(period_s),
            smoother: PathSmoother::new(max_samples),
            shapers: std::array::from_fn(|_| InputShaper::new(GROUP_MIN_SHAPER_HZ, period_s)),
            period_s,
            sample: Sample::default(),
            pose_cmd: Kinematics6::default(),
            faults: 0,
            commander: None,
        }
    }

    /// The axes, in the order added.
    pub fn axes(&self) -> &[u8] {
        &self.axes[..self.count]
    }

    /// The axes and how many there are, by value (the caller may change the kernel).
    pub fn members(&self) -> ([u8; MAX_GROUP_AXES], usize) {
        (self.axes, self.count)
    }

    /// Where the group is among its states (IsGrpEnabled, IsGrpErrorStop: HMPL 8.4.1, 8.4.4).
    pub fn state(&self) -> GroupState {
        self.state
    }

    /// Not `Disabled`: EnableGroup has run, and an ErrorStop counts as enabled.
    pub fn is_enabled(&self) -> bool {
        self.state != GroupState::Disabled
    }

    /// The interpolator, or the smoothing or shaping after it, still moves the pose.
    pub fn is_moving(&self) -> bool {
        self.state == GroupState::Standby
            && (self.planner.is_moving() || !self.smoother.settled() || !self.shapers_settled())
    }

    pub(crate) fn commander(&self) -> Option<u8> {
        self.commander
    }

    /// Commands in the buffer, the one under way included (HMPL 8.3.27).
    pub fn commands(&self) -> usize {
        self.planner.commands()
    }

    /// StopAll (HMPL 2.8): an enabled group stops along its path.
    pub fn stop(&mut self) {
        if self.state == GroupState::Standby {
            self.planner.stop();
        }
    }

    pub(crate) fn claim(&mut self, task: u8) {
        self.commander = Some(task);
    }

    /// MCS coordinates the group has an axis for (Cartesian: one per axis, at most 6).
    fn coordinates(&self) -> usize {
        self.count.min(COORDINATES)
    }

    /// The smooth time of the group's S-curve, ms: the linear (TCP) profile's (HMPL 8.3.6,
    /// 8.3.19); one moving average smooths all coordinates (docs/decisions.md, "Groups").
    fn smooth_ms(&self) -> f64 {
        self.settings.lin.smooth_ms
    }

    /// The moving average's window for the group's smooth time: the planner holds every
    /// full stop for ceil(Ts / cycle) cycles, so a window this long comes to rest there.
    fn samples(&self) -> usize {
        (self.smooth_ms() / 1000.0 / self.period_s).ceil() as usize + 1
    }

    /// Stands still at `pose`: the interpolator, the smoothing and the command.
    fn rest_at(&mut self, pose: Pose) {
        self.planner.rest_at(pose);
        self.smoother.reset(pose, 0.0, self.samples());
        for (shaper, &p) in self.shapers.iter_mut().zip(&pose) {
            shaper.rest_at(p);
        }
        self.pose_cmd = Kinematics6 { pos: pose, ..Kinematics6::default() };
        self.sample = Sample { pose, ..Sample::default() };
    }

    /// One cycle of the interpolator, smoothed: the pose the axes take.
    fn step(&mut self) -> &Kinematics6 {
        let len = self.samples();
        if !self.is_moving() && self.smoother.window() != len {
            // A new smooth time takes effect at rest (docs/decisions.md, "Groups").
            self.smoother.reset(self.pose_cmd.pos, self.sample.path_pos, len);
        }
        self.sample = self.planner.step();
        let smoothed = self.smoother.push(&self.sample);
        let previous = self.pose_cmd;
        for (i, (shaper, &pos)) in self.shapers.iter_mut().zip(&smoothed).enumerate() {
            let k = shaper.push(Kinematics { pos, vel: 0.0, acc: 0.0 });
            self.pose_cmd.pos[i] = k.pos;
            self.pose_cmd.vel[i] = (k.pos - previous.pos[i]) / self.period_s;
            self.pose_cmd.acc[i] = (self.pose_cmd.vel[i] - previous.vel[i]) / self.period_s;
        }
        if !self.is_moving() {
            // At rest the pose no longer changes: its velocity is 0, not the last step's.
            (self.pose_cmd.vel, self.pose_cmd.acc) = ([0.0; COORDINATES], [0.0; COORDINATES]);
        }
        &self.pose_cmd
    }

    /// The per-coordinate limits the interpolator keeps: each axis' own (HMPL 8.1).
    fn limits(&self, axes: &[crate::axis::Axis]) -> Limits {
        let mut limits = Limits { max_vel: [f64::INFINITY; COORDINATES], max_acc: [f64::INFINITY; COORDINATES] };
        for (i, &a) in self.axes().iter().take(COORDINATES).enumerate() {
            let s = axes[a as usize].settings();
            limits.max_vel[i] = s.max_vel;
            limits.max_acc[i] = s.max_acc;
        }
        limits
    }

    /// `carte_pose_fb` (table 8.1.1.1): the axes' feedback, Cartesian kinematics.
    pub fn pose_fb(&self, axes: &[crate::axis::Axis]) -> Pose {
        let mut pose = [0.0; COORDINATES];
        for (p, &a) in pose.iter_mut().zip(self.axes()) {
            *p = axes[a as usize].pos_fb();
        }
        pose
    }

    /// The group as the status functions see it (HMPL tables 8.1.1.1 to 8.1.1.5).
    pub fn snapshot(&self, axes: &[crate::axis::Axis]) -> GroupSnapshot {
        let members = || self.axes().iter().map(|&a| &axes[a as usize]);
        let moving = self.is_moving();
        let mut motion_status = 0;
        if self.is_enabled() {
            motion_status |= group_motion_status::ENABLED;
        }
        if moving {
            motion_status |= group_motion_status::MOVING;
        }
        if self.in_shape() {
            motion_status |= group_motion_status::INPUT_SHAPE;
        }
        // HMPL 8.1: the group is in position when all its axes are (no window of its own).
        if self.count > 0 && !moving && members().all(|a| a.is_in_position()) {
            motion_status |= group_motion_status::IN_POSITION;
        }
        let mut fault_status = self.faults;
        if self.state == GroupState::ErrorStop {
            fault_status |= group_fault_status::ERROR_STOP;
        }
        GroupSnapshot {
            motion_status,
            fault_status,
            axis_count: self.count as u32,
            kin: self.kin as u32,
            coord_sys: self.coord_sys.flags() as u32,
            buffer_mode: i64::from(self.settings.buffer) as u32,
            trans_mode: i64::from(self.trans_mode) as u32,
            cmd_num: self.planner.commands() as u32,
            queue_size: self.planner.queue_size() as u32,
            axes: self.axes,
            lin_profile: profile_words(&self.settings.lin),
            ang_profile: profile_words(&self.settings.ang),
            vel_scale: self.settings.vel_scale,
            carte_pose_cmd: self.pose_cmd.pos,
            carte_vel_cmd: self.pose_cmd.vel,
            carte_pose_fb: self.pose_fb(axes),
            grp_pg: [self.sample.path_pos, self.sample.path_vel, self.sample.path_acc],
        }
    }
}

fn profile_words(p: &path::planner::Profile) -> [f64; 4] {
    [p.vel, p.acc, p.dec, p.smooth_ms]
}

impl super::Kernel {
    /// The group a script names, or HMPL's "argument out of range".
    fn group_id(&self, id: i64) -> Result<u8, ErrorCode> {
        usize::try_from(id)
            .ok()
            .filter(|&g| g < self.groups.len())
            .map(|g| g as u8)
            .ok_or(ErrorCode::System(api::SystemError::HmplArgOutOfRange))
    }

    /// Records a refusal as group `g`'s last error (HMPL 18.5) and returns its code.
    fn refuse_group(&mut self, g: u8, error: GroupError) -> ErrorCode {
        let code = ErrorCode::group(g, error);
        self.group_last_err[g as usize] = code.code();
        code
    }

    /// The groups, by id, all [`crate::MAX_GROUPS`] of them, used or not.
    pub fn groups(&self) -> &[Group] {
        &self.groups
    }

    /// The group a script names, or HMPL's "argument out of range".
    pub fn group(&self, id: i64) -> Result<&Group, ErrorCode> {
        Ok(&self.groups[self.group_id(id)? as usize])
    }

    /// Task `task` set the group's present motion going (fault reactions, HMPL 16).
    pub fn claim_group(&mut self, id: i64, task: u8) {
        if let Ok(g) = self.group_id(id) {
            self.groups[g as usize].claim(task);
        }
    }

    /// The group's stage of `Kernel::step`, after the axes' own sources: each enabled
    /// group reacts to its axes' faults (HMPL table 8.1.1.4), then steps its interpolator
    /// and gives its synced axes their references.
    pub(super) fn step_groups(&mut self) {
        for g in 0..self.groups.len() {
            if self.groups[g].state != GroupState::Standby {
                continue;
            }
            if let Some((bit, error)) = self.group_fault(g) {
                self.error_stop_group(g, bit, error);
                continue;
            }
            let group = &mut self.groups[g];
            let pose = *group.step();
            let n = group.coordinates();
            for (i, &a) in group.axes[..n].iter().enumerate() {
                let k = Kinematics { pos: pose.pos[i], vel: pose.vel[i], acc: pose.acc[i] };
                self.axes[a as usize].follow_group(k);
            }
        }
    }

    /// Why an enabled group must stop: an axis disabled or faulted (Axis Fault), or in error
    /// stop at a software limit (Software Limit), with the group error it records.
    fn group_fault(&self, g: usize) -> Option<(u32, GroupError)> {
        let sw = fault_status::SW_LEFT_LIMIT | fault_status::SW_RIGHT_LIMIT;
        let members = self.groups[g].axes().iter().map(|&a| &self.axes[a as usize]);
        let mut found = None;
        for axis in members {
            if !axis.is_enabled() || axis.fault_status() & fault_status::DRIVE_FAULT != 0 {
                return Some((group_fault_status::AXIS_FAULT, GroupError::AxisAbnormallyDisabled));
            }
            if axis.is_error_stop() {
                found = Some(if axis.fault_status() & sw != 0 {
                    (group_fault_status::SOFTWARE_LIMIT, GroupError::AxisSwl)
                } else {
                    (group_fault_status::AXIS_FAULT, GroupError::AxisAbnormallyDisabled)
                });
            }
        }
        found
    }

    /// Group Error Stop: every axis leaves sync and comes to rest with its kill
    /// deceleration; the queue is dropped.
    fn error_stop_group(&mut self, g: usize, bit: u32, error: GroupError) {
        self.groups[g].state = GroupState::ErrorStop;
        self.groups[g].faults |= bit;
        self.refuse_group(g as u8, error);
        self.release_group_axes(g, true);
    }

    /// The axes of group `g` leave sync: each comes to rest on its own generator, with its
    /// kill deceleration (`fault`) or its deceleration, or stays where it is if the group
    /// stands; the interpolator forgets its plan.
    fn release_group_axes(&mut self, g: usize, fault: bool) {
        let count = self.groups[g].count;
        let at_rest = !self.groups[g].is_moving();
        for i in 0..count {
            let a = self.groups[g].axes[i] as usize;
            let dec = if fault { self.axes[a].settings().kill_dec } else { self.axes[a].settings().dec };
            self.axes[a].leave_group_sync(dec, at_rest);
        }
        let pose = self.groups[g].pose_cmd.pos;
        self.groups[g].rest_at(pose);
    }

    /// The pose the group's axes stand at (their references), MCS.
    fn pose_of_axes(&self, g: usize) -> Pose {
        let mut pose = [0.0; COORDINATES];
        let group = &self.groups[g];
        for (i, &a) in group.axes[..group.coordinates()].iter().enumerate() {
            pose[i] = self.axes[a as usize].reference().pos;
        }
        pose
    }

    /// A task failed or was stopped: the groups it set going react as its fault reaction
    /// says; other tasks' groups go on.
    pub(super) fn react_groups(&mut self, task: u8, reaction: config::FaultReaction) {
        use config::FaultReaction;
        for g in 0..self.groups.len() {
            let group = &self.groups[g];
            if group.commander != Some(task) || !group.is_moving() {
                continue;
            }
            match reaction {
                FaultReaction::None => {}
                FaultReaction::Decelerate | FaultReaction::QuickStop => self.groups[g].planner.stop(),
                FaultReaction::Disable => {
                    for i in 0..self.groups[g].count {
                        let a = self.groups[g].axes[i];
                        let _ = self.disable(a as i64);
                    }
                }
            }
        }
    }

    /// Whether axis `a` is in a group (its own fault reactions are the group's).
    pub(super) fn is_grouped(&self, a: usize) -> bool {
        self.axes[a].source().group().is_some()
    }
}
