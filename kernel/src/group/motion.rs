//! Path commands of HMPL 8.2.9 to 8.2.17 and 8.5: each is made a segment in MCS from
//! where the queued path ends (or, with BM_ABORT, from where the motion under way can
//! stop) and queued on the group's interpolator with the corner transition of table
//! 8.1.5.1 before it (`Planner::push_with_transition`). The coordinate systems (HMPL 8.1.2) are applied here, so the
//! interpolator only ever sees MCS.

use api::call::Doubles;
use api::{ErrorCode, GroupError, Quantity};
use path::blend::{TransitionMode, TransitionParams};
use path::commands;
use path::frames::{CoordSys, Frame};
use path::planner::{BufferMode, Motion, Profile};
use path::{Pose, Segment};

use super::settings::profile_from;
use super::{COORDINATES, GroupState};
use crate::Kernel;

/// A path command as the script gave it, in the coordinate system it names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PathCommand {
    /// LineAbs2D/3D, LineAbs (HMPL 8.2.9, 8.2.10, 8.5.1): the coordinates given; the others
    /// keep the start's.
    LineAbs {
        /// X, Y, Z mm, A, B, C deg; `None` where the command gives no coordinate.
        target: [Option<f64>; COORDINATES],
    },
    /// LineRel2D/3D, LineRel (HMPL 8.2.11, 8.2.12, 8.5.2).
    LineRel {
        /// The displacement X, Y, Z mm, A, B, C deg; 0 where the command gives none.
        distance: Pose,
    },
    /// Arc2D (HMPL 8.2.13): through `border` to `end`.
    Arc2D {
        /// A point the arc passes, (x, y) mm.
        border: [f64; 2],
        /// Where it ends, (x, y) mm.
        end: [f64; 2],
    },
    /// ArcCW2D, ArcCCW2D (HMPL 8.2.14, 8.2.15).
    ArcCenter2D {
        /// The arc's center, (x, y) mm.
        center: [f64; 2],
        /// Where it ends, (x, y) mm.
        end: [f64; 2],
        /// ArcCCW2D: counter-clockwise; else ArcCW2D.
        ccw: bool,
    },
    /// ArcAngle2D (HMPL 8.2.16).
    ArcAngle2D {
        /// The arc's center, (x, y) mm.
        center: [f64; 2],
        /// The turning angle, deg, > 0 counter-clockwise; several turns allowed.
        angle: f64,
    },
    /// Circle2D (HMPL 8.2.17).
    Circle2D {
        /// The circle's center, (x, y) mm.
        center: [f64; 2],
        /// Where it ends, (x, y) mm.
        end: [f64; 2],
        /// The manual's turns rule: ≥ 1 counter-clockwise, < 0 clockwise, 0 as 1.
        turns: i64,
    },
    /// CircleAbs, CircleRel (HMPL 8.5.3, 8.5.4).
    Circle {
        /// A point of the axis it turns about, mm.
        center: [f64; 3],
        /// That axis' direction (right-hand rule for the turning sense).
        normal: [f64; 3],
        /// The turns rule of Circle2D.
        turns: i64,
        /// The 6-DOF end, or with `relative` the distance to it.
        target: Pose,
        /// CircleRel: `target` is a distance from the start.
        relative: bool,
    },
}

impl PathCommand {
    /// LineAbs2D, LineAbs3D.
    pub fn line_abs<const N: usize>(end: [f64; N]) -> Self {
        PathCommand::LineAbs { target: std::array::from_fn(|i| end.get(i).copied()) }
    }

    /// LineRel2D, LineRel3D.
    pub fn line_rel<const N: usize>(distance: [f64; N]) -> Self {
        PathCommand::LineRel { distance: std::array::from_fn(|i| distance.get(i).copied().unwrap_or(0.0)) }
    }

    /// The segment in MCS from `start` (MCS), the command's points mapped by `frame`.
    fn segment(&self, start: &Pose, frame: &Frame) -> Result<Segment, GroupError> {
        let normal = frame.z_axis();
        match *self {
            PathCommand::LineAbs { target } => {
                let seen = frame.pose_from_mcs(start);
                let target: Pose = std::array::from_fn(|i| target[i].unwrap_or(seen[i]));
                commands::line_abs(start, &frame.pose_to_mcs(&target))
            }
            PathCommand::LineRel { distance } => commands::line_abs(start, &frame.relative_target(start, &distance)),
            PathCommand::Arc2D { border, end } => {
                commands::arc_2d(start, frame.point_2d(start, border), frame.point_2d(start, end))
            }
            PathCommand::ArcCenter2D { center, end, ccw } => {
                let (center, end) = (frame.point_2d(start, center), frame.point_2d(start, end));
                if ccw {
                    commands::arc_ccw_2d(start, center, end, normal)
                } else {
                    commands::arc_cw_2d(start, center, end, normal)
                }
            }
            PathCommand::ArcAngle2D { center, angle } => {
                commands::arc_angle_2d(start, frame.point_2d(start, center), normal, angle)
            }
            PathCommand::Circle2D { center, end, turns } => {
                commands::circle_2d(start, frame.point_2d(start, center), frame.point_2d(start, end), normal, turns)
            }
            PathCommand::Circle { center, normal, turns, target, relative } => {
                let target = if relative { frame.relative_target(start, &target) } else { frame.pose_to_mcs(&target) };
                let (center, normal) = (frame.point_to_mcs(center), frame.vector_to_mcs(normal));
                commands::circle_abs(start, center, normal, turns, &target)
            }
        }
    }
}

/// What an HMPL 8.5 command brings of its own: profile, coordinate system, buffer and
/// transition modes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advanced {
    /// `motion_profile`: the command's own linear profile (HMPL 8.5).
    pub profile: Profile,
    /// `coord_sys`: the system its points are in (HMPL 8.1.2).
    pub coord_sys: CoordSys,
    /// `buff_mode`: how it joins the next command (HMPL table 8.1.4.1).
    pub buffer: BufferMode,
    /// `trans_mode`: the corner transition before it (HMPL table 8.1.5.1).
    pub trans_mode: TransitionMode,
    /// `trans_par`: that transition's parameters (HMPL 8.3.26).
    pub trans: TransitionParams,
}

impl Advanced {
    /// `motion_profile` (4 numbers, ranges checked with the arguments), `coord_sys`,
    /// `buff_mode`, `trans_mode`, `trans_par` (4 numbers; empty or 0 with TM_NONE).
    pub fn new(
        profile: &[f64],
        coord_sys: i64,
        buff_mode: i64,
        trans_mode: i64,
        trans: &[f64],
    ) -> Result<Self, GroupError> {
        let trans_mode = TransitionMode::try_from(trans_mode)?;
        let trans = match trans {
            [trans_vel, trans_dis, trans_dev, trans_curv, ..] => TransitionParams {
                trans_vel: *trans_vel,
                trans_dis: *trans_dis,
                trans_dev: *trans_dev,
                trans_curv: *trans_curv,
            },
            _ if trans_mode == TransitionMode::None => TransitionParams::default(),
            _ => return Err(GroupError::CmdInvalidTransVel),
        };
        trans.validate_for(trans_mode)?;
        Ok(Advanced {
            profile: profile_from(profile)?,
            coord_sys: CoordSys::parse(coord_sys, true)?,
            buffer: BufferMode::try_from(buff_mode)?,
            trans_mode,
            trans,
        })
    }
}

impl Kernel {
    /// A refusal of group `group` as its last error; a group id out of range as the system's.
    pub fn group_refusal(&mut self, group: i64, error: GroupError) -> ErrorCode {
        match self.group_id(group) {
            Ok(g) => self.refuse_group(g, error),
            Err(e) => e,
        }
    }

    /// Queues a path command (HMPL 8.2.9 to 8.2.17, 8.5). Refused unless the group is
    /// enabled and out of error stop; a full queue refuses it with 0x82II0078 and keeps
    /// everything queued.
    pub fn move_group(
        &mut self,
        group: i64,
        command: PathCommand,
        advanced: Option<Advanced>,
    ) -> Result<(), ErrorCode> {
        let g = self.group_id(group)?;
        self.queue_path(g as usize, command, advanced).map_err(|e| self.refuse_group(g, e))
    }

    fn queue_path(&mut self, g: usize, command: PathCommand, advanced: Option<Advanced>) -> Result<(), GroupError> {
        match self.groups[g].state {
            GroupState::Disabled => return Err(GroupError::CmdInvalidDisabled),
            GroupState::ErrorStop => return Err(GroupError::CmdInvalidState),
            GroupState::Standby => {}
        }
        let limits = self.groups[g].limits(&self.axes);
        let grp = &mut self.groups[g];
        let (mut motion, coord_sys, trans_mode, trans) = match advanced {
            Some(a) => {
                (Motion { lin: a.profile, ang: grp.settings.ang, buffer: a.buffer }, a.coord_sys, a.trans_mode, a.trans)
            }
            None => (grp.settings.motion(), grp.coord_sys, grp.trans_mode, grp.trans),
        };
        // One moving average smooths the whole path: its smooth time is the group's, which
        // the planner's full stops must last (docs/decisions.md, "Groups").
        let smooth_ms = grp.smooth_ms();
        (motion.lin.smooth_ms, motion.ang.smooth_ms) = (smooth_ms, smooth_ms);
        let start =
            if motion.buffer == BufferMode::Abort { grp.planner.stopping_pose() } else { grp.planner.end_pose() };
        let frame = grp.frames.frame(coord_sys);
        let segment = command.segment(&start, &frame)?;
        // Cartesian kinematics: a coordinate the group has no axis for stays where it is, and
        // each axis' end is a target it can reach (its drive's counts).
        let end = segment.end();
        if (grp.coordinates()..COORDINATES).any(|i| (end[i] - start[i]).abs() > 1e-9) {
            return Err(GroupError::CmdInvalidPos);
        }
        let axes = &self.axes;
        if grp.axes().iter().zip(&end).any(|(&a, &p)| !axes[a as usize].accepts(Quantity::Target, p)) {
            return Err(GroupError::CmdInvalidPos);
        }
        grp.planner.push_with_transition(segment, motion, trans_mode, &trans, &limits).map(drop)
    }

    /// HMPL 8.3.21: the coordinate system of later targets.
    pub fn set_grp_coord_sys(&mut self, group: i64, coord_sys: i64) -> Result<(), ErrorCode> {
        let g = self.group_id(group)?;
        match CoordSys::parse(coord_sys, true) {
            Ok(cs) => {
                self.groups[g as usize].coord_sys = cs;
                Ok(())
            }
            Err(e) => Err(self.refuse_group(g, e)),
        }
    }

    /// HMPL 8.3.25: the transition mode of later junctions, TM_NONE .. TM_MAX_CORNER_CURV.
    pub fn set_grp_trans_mode(&mut self, group: i64, trans_mode: i64) -> Result<(), ErrorCode> {
        let g = self.group_id(group)?;
        match TransitionMode::try_from(trans_mode) {
            Ok(mode) => {
                self.groups[g as usize].trans_mode = mode;
                Ok(())
            }
            Err(e) => Err(self.refuse_group(g, e)),
        }
    }

    /// HMPL 8.3.26: the transition parameters, in the ranges of table 8.3.26.1 that do not
    /// depend on the segments.
    pub fn set_grp_trans_prm(
        &mut self,
        group: i64,
        [trans_vel, trans_dis, trans_dev, trans_curv]: [f64; 4],
    ) -> Result<(), ErrorCode> {
        let g = self.group_id(group)?;
        let trans = TransitionParams { trans_vel, trans_dis, trans_dev, trans_curv };
        match trans.validate() {
            Ok(()) => {
                self.groups[g as usize].trans = trans;
                Ok(())
            }
            Err(e) => Err(self.refuse_group(g, e)),
        }
    }

    /// HMPL 8.3.30: the transform of CS_PCS, CS_WCSn or CS_OFFSET.
    pub fn grp_coord_trans(&mut self, group: i64, coord_sys: i64) -> Result<Pose, ErrorCode> {
        let g = self.group_id(group)?;
        self.groups[g as usize].frames.get(coord_sys).map_err(|e| self.refuse_group(g, e))
    }

    /// HMPL 8.3.31: sets the transform of CS_PCS, CS_WCSn or CS_OFFSET; targets queued
    /// before keep the transform they were given in.
    pub fn set_grp_coord_trans(&mut self, group: i64, coord_sys: i64, params: &Doubles) -> Result<(), ErrorCode> {
        let g = self.group_id(group)?;
        let result = match params.len() {
            6.. => {
                self.groups[g as usize].frames.set(coord_sys, &std::array::from_fn(|i| params.get(i).unwrap_or(0.0)))
            }
            _ => Err(GroupError::CmdCoordInvalidParam),
        };
        result.map_err(|e| self.refuse_group(g, e))
    }

    /// HMPL 8.3.32, 8.3.33: the commanded pose or the pose of the feedback in a coordinate
    /// system (CS_ACS: the axes' own positions, which Cartesian kinematics make MCS).
    pub fn grp_pose(&mut self, group: i64, coord_sys: i64, feedback: bool) -> Result<Pose, ErrorCode> {
        let g = self.group_id(group)?;
        let cs = CoordSys::parse(coord_sys, true).map_err(|e| self.refuse_group(g, e))?;
        let grp = &self.groups[g as usize];
        let mcs = if feedback { grp.pose_fb(&self.axes) } else { grp.pose_cmd.pos };
        Ok(grp.frames.frame(cs).pose_from_mcs(&mcs))
    }
}
