//! The coordinate systems of a group (HMPL 8.1.2): MCS, the machine's, and the systems a
//! program may work in: PCS (product), WCS1..15 (workpieces), OFFSET (a temporary zero),
//! each a transform {X, Y, Z mm, A, B, C deg} set per group with SetGrpCoordTrans.
//!
//! A transform places its system in its parent: p_parent = R·p + t with the fixed-frame
//! roll-pitch-yaw rotation R = Rz(C)·Ry(B)·Rx(A). The chain is MCS → OFFSET → WCSn → PCS,
//! so a point given in a combination of systems is in MCS
//! p_MCS = T_OFFSET · T_WCSn · T_PCS · p, each factor present only where its flag is.
//! HMPL 8.1.6 example 5-1: PCS {400, 200, 0, 0, 0, 45} maps (10, 10) to (400, 200 + 10√2).

use api::GroupError;
use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};

use crate::segment::Pose;

// The flags of HMPL table 8.1.2.1, with the values of api's `CS_*` constants.
/// The machine coordinate system, where the group's targets finally are.
pub const CS_MCS: i64 = 0x1;
/// The product coordinate system, innermost of the chain MCS → OFFSET → WCSn → PCS.
pub const CS_PCS: i64 = 0x2;
/// The temporary zero, outermost of the chain, placed directly in MCS.
pub const CS_OFFSET: i64 = 0x4;
/// Named by the manual, not supported: refused.
pub const CS_GLOBAL: i64 = 0x8;
/// The axes' own positions, where a command allows them (`CoordSys::parse`).
pub const CS_ACS: i64 = 0x10;
/// CS_WCSn = n << 8, n = 1..15.
pub const CS_WCS_SHIFT: u32 = 8;
const WCS_MASK: i64 = 0xF << CS_WCS_SHIFT;

/// The number of workpiece systems.
pub const WCS_COUNT: usize = 15;

/// A coordinate system as its flags select it (HMPL 8.1.2: "CS_OFFSET | CS_WCS2 | CS_PCS").
/// All fields off is MCS.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoordSys {
    /// CS_OFFSET is in the chain.
    pub offset: bool,
    /// The workpiece system n of CS_WCSn, 1..=15; `None` where no WCS is in the chain.
    pub wcs: Option<u8>,
    /// CS_PCS is in the chain.
    pub pcs: bool,
    /// The axes' own positions; only where the caller allows it (`parse`).
    pub acs: bool,
}

impl CoordSys {
    /// CS_MCS: no transform, the group's default system.
    pub const MCS: CoordSys = CoordSys { offset: false, wcs: None, pcs: false, acs: false };

    /// The system the flags name. `CmdCoordSysUnknown` for 0, unknown bits, CS_GLOBAL,
    /// CS_MCS or CS_ACS together with another flag, and CS_ACS where `allow_acs` is false.
    /// (Two WCS flags OR'ed make another WCS number: the 4-bit field cannot tell.)
    pub fn parse(flags: i64, allow_acs: bool) -> Result<CoordSys, GroupError> {
        let known = CS_MCS | CS_PCS | CS_OFFSET | CS_ACS | WCS_MASK;
        if flags <= 0 || flags & !known != 0 {
            return Err(GroupError::CmdCoordSysUnknown);
        }
        match flags {
            CS_MCS => return Ok(CoordSys::MCS),
            CS_ACS if allow_acs => return Ok(CoordSys { acs: true, ..CoordSys::MCS }),
            _ if flags & (CS_MCS | CS_ACS) != 0 => return Err(GroupError::CmdCoordSysUnknown),
            _ => {}
        }
        let n = (flags & WCS_MASK) >> CS_WCS_SHIFT;
        Ok(CoordSys {
            offset: flags & CS_OFFSET != 0,
            wcs: (n != 0).then_some(n as u8),
            pcs: flags & CS_PCS != 0,
            acs: false,
        })
    }

    /// The flags, as GetGrpCoordSys returns them.
    pub fn flags(&self) -> i64 {
        if self.acs {
            return CS_ACS;
        }
        let mut flags = i64::from(self.wcs.unwrap_or(0)) << CS_WCS_SHIFT;
        if self.offset {
            flags |= CS_OFFSET;
        }
        if self.pcs {
            flags |= CS_PCS;
        }
        if flags == 0 { CS_MCS } else { flags }
    }
}

/// A group's transforms (HMPL 8.3.30, 8.3.31); all identity by default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Frames {
    /// PCS, WCS1..15, OFFSET.
    transforms: [Pose; WCS_COUNT + 2],
}

const OFFSET_SLOT: usize = WCS_COUNT + 1;

impl Frames {
    /// SetGrpCoordTrans: `coord_sys` names exactly one of CS_PCS, CS_WCSn, CS_OFFSET
    /// (else `CmdCoordSysUnknown`); a value that is no finite number is
    /// `CmdCoordInvalidParam`.
    pub fn set(&mut self, coord_sys: i64, params: &Pose) -> Result<(), GroupError> {
        let slot = Self::slot(coord_sys)?;
        if !params.iter().all(|v| v.is_finite()) {
            return Err(GroupError::CmdCoordInvalidParam);
        }
        self.transforms[slot] = *params;
        Ok(())
    }

    /// GetGrpCoordTrans.
    pub fn get(&self, coord_sys: i64) -> Result<Pose, GroupError> {
        Ok(self.transforms[Self::slot(coord_sys)?])
    }

    fn slot(coord_sys: i64) -> Result<usize, GroupError> {
        match coord_sys {
            CS_PCS => Ok(0),
            CS_OFFSET => Ok(OFFSET_SLOT),
            _ if coord_sys & !WCS_MASK == 0 && coord_sys != 0 => Ok((coord_sys >> CS_WCS_SHIFT) as usize),
            _ => Err(GroupError::CmdCoordSysUnknown),
        }
    }

    /// The transform from `cs` to MCS: T_OFFSET · T_WCSn · T_PCS for the flags present
    /// (identity for MCS and ACS; the caller maps ACS through the kinematics).
    pub fn frame(&self, cs: CoordSys) -> Frame {
        let mut frame = Frame::identity();
        if cs.offset {
            frame = frame.then(&Frame::from_params(&self.transforms[OFFSET_SLOT]));
        }
        if let Some(n) = cs.wcs {
            frame = frame.then(&Frame::from_params(&self.transforms[usize::from(n)]));
        }
        if cs.pcs {
            frame = frame.then(&Frame::from_params(&self.transforms[0]));
        }
        frame
    }
}

/// A rigid transform from one coordinate system to MCS.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    iso: Isometry3<f64>,
    /// Whether any factor rotates: without rotation A, B, C pass unchanged.
    rotates: bool,
}

impl Frame {
    /// MCS itself.
    pub fn identity() -> Frame {
        Frame { iso: Isometry3::identity(), rotates: false }
    }

    /// The transform {X, Y, Z, A, B, C} (HMPL 8.3.31) as a frame.
    pub fn from_params(p: &Pose) -> Frame {
        Frame {
            iso: Isometry3::from_parts(
                Translation3::new(p[0], p[1], p[2]),
                UnitQuaternion::from_rotation_matrix(&rpy(&[p[3], p[4], p[5]])),
            ),
            rotates: p[3] != 0.0 || p[4] != 0.0 || p[5] != 0.0,
        }
    }

    /// `self · inner`: `inner`'s system placed in `self`'s.
    pub fn then(&self, inner: &Frame) -> Frame {
        Frame { iso: self.iso * inner.iso, rotates: self.rotates || inner.rotates }
    }

    /// A point of this system in MCS: rotated and translated.
    pub fn point_to_mcs(&self, p: [f64; 3]) -> [f64; 3] {
        (self.iso * Point3::from(p)).coords.into()
    }

    /// A point of MCS in this system: the inverse of [`Self::point_to_mcs`].
    pub fn point_from_mcs(&self, p: [f64; 3]) -> [f64; 3] {
        self.iso.inverse_transform_point(&Point3::from(p)).coords.into()
    }

    /// A direction or displacement (normal vectors, relative moves): rotated only.
    pub fn vector_to_mcs(&self, v: [f64; 3]) -> [f64; 3] {
        (self.iso.rotation * Vector3::from(v)).into()
    }

    /// A direction of MCS in this system: the inverse of [`Self::vector_to_mcs`].
    pub fn vector_from_mcs(&self, v: [f64; 3]) -> [f64; 3] {
        self.iso.rotation.inverse_transform_vector(&Vector3::from(v)).into()
    }

    /// The system's Z axis in MCS: the normal of its XY plane, where 2-D commands draw.
    pub fn z_axis(&self) -> [f64; 3] {
        self.vector_to_mcs([0.0, 0.0, 1.0])
    }

    /// The 2-D point (x, y) of the system at the height the start pose has in it, in MCS.
    pub fn point_2d(&self, start_mcs: &Pose, xy: [f64; 2]) -> [f64; 3] {
        let z = self.point_from_mcs([start_mcs[0], start_mcs[1], start_mcs[2]])[2];
        self.point_to_mcs([xy[0], xy[1], z])
    }

    /// A pose given in this system (a command's target) in MCS. The orientation is composed
    /// through rotation matrices; of the equal angle triples the one nearest the given
    /// angles is returned, so a turn of C = 270° stays 270°, not -90°.
    pub fn pose_to_mcs(&self, pose: &Pose) -> Pose {
        let p = self.point_to_mcs([pose[0], pose[1], pose[2]]);
        let abc = [pose[3], pose[4], pose[5]];
        let abc = if self.rotates { angles(&(self.iso.rotation.to_rotation_matrix() * rpy(&abc)), &abc) } else { abc };
        [p[0], p[1], p[2], abc[0], abc[1], abc[2]]
    }

    /// A pose in MCS (the command or feedback) in this system (GetGrpPoseCmd/Fb).
    pub fn pose_from_mcs(&self, pose: &Pose) -> Pose {
        let p = self.point_from_mcs([pose[0], pose[1], pose[2]]);
        let abc = [pose[3], pose[4], pose[5]];
        let abc = if self.rotates {
            angles(&(self.iso.rotation.to_rotation_matrix().inverse() * rpy(&abc)), &abc)
        } else {
            abc
        };
        [p[0], p[1], p[2], abc[0], abc[1], abc[2]]
    }

    /// The MCS target of a relative move `delta` given in this system: the start seen in
    /// the system plus `delta`, coordinate by coordinate (LineRel, CircleRel, HMPL 8.5.2).
    pub fn relative_target(&self, start_mcs: &Pose, delta: &Pose) -> Pose {
        let start = self.pose_from_mcs(start_mcs);
        self.pose_to_mcs(&std::array::from_fn(|i| start[i] + delta[i]))
    }
}

/// R = Rz(C)·Ry(B)·Rx(A) for A, B, C in degrees (HMPL 8.1.2).
pub fn rpy(abc: &[f64; 3]) -> Rotation3<f64> {
    Rotation3::from_euler_angles(abc[0].to_radians(), abc[1].to_radians(), abc[2].to_radians())
}

/// The A, B, C (deg) of `r` nearest to `near`: both solutions of the decomposition, each
/// angle moved by whole turns towards `near`. At B = ±90° (gimbal lock) only A ∓ C is
/// defined; A is then taken from `near`.
pub fn angles(r: &Rotation3<f64>, near: &[f64; 3]) -> [f64; 3] {
    let m = r.matrix();
    let b = (-m[(2, 0)]).atan2(m[(0, 0)].hypot(m[(1, 0)]));
    let candidates = if b.cos() > 1e-9 {
        let (a, c) = (m[(2, 1)].atan2(m[(2, 2)]), m[(1, 0)].atan2(m[(0, 0)]));
        let pi = std::f64::consts::PI;
        [[a, b, c], [a + pi, pi - b, c + pi]]
    } else {
        let a = near[0].to_radians();
        let c = if b > 0.0 { a - m[(0, 1)].atan2(m[(0, 2)]) } else { (-m[(0, 1)]).atan2(-m[(0, 2)]) - a };
        [[a, b, c]; 2]
    };
    let unwrapped =
        candidates.map(|abc| std::array::from_fn::<f64, 3, _>(|i| nearest_turn(abc[i].to_degrees(), near[i])));
    let distance = |x: &[f64; 3]| (0..3).map(|i| (x[i] - near[i]).powi(2)).sum::<f64>();
    if distance(&unwrapped[1]) < distance(&unwrapped[0]) { unwrapped[1] } else { unwrapped[0] }
}

/// `deg` plus the whole turns that bring it nearest to `near`.
fn nearest_turn(deg: f64, near: f64) -> f64 {
    deg + ((near - deg) / 360.0).round() * 360.0
}
