//! Which source drives an axis' reference: one value per axis, changed only by the
//! transitions below, each of which refuses what the axis' state does not allow with the
//! manual's error code (HMPL ch. 18, axis error table).
//!
//! - `Profile`: the axis' own profile generator, through its filter chain (HMPL 5.1, 5.2).
//! - `Gear`: a gear slave (HMPL ch. 6). Engaged, the reference is its master's, scaled
//!   (6.1); not engaged, the generator brings it to rest and holds it. The slave's own
//!   motion commands are refused (0x83II00A0).
//! - `Homing`: the drive's homing mode moves the motor (HMPL 20.2); the reference
//!   follows the feedback.
//! - `Torque`: cyclic synchronous torque (HMPL 5.2.7, 5.3.41); the reference follows the
//!   feedback and the drive gets the torque.
//!
//! - `Group`: an axis of a group (HMPL ch. 8). In sync, the group's interpolator gives its
//!   reference (the kernel steps the groups after the axes' own sources, as gear masters
//!   move before their slaves); out of sync (group disabled or in error stop), the axis'
//!   generator brings it to rest and holds it. Its own motion is refused (0x83II00E6).

use api::AxisError;

use crate::homing::Homing;
use devices::profile::Kinematics;

/// An engaged gear: slave = slave origin + ratio x (master - master origin) (HMPL 6.1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Engagement {
    pub ratio: f64,
    pub master_origin: f64,
    pub slave_origin: f64,
}

impl Engagement {
    /// The slave's reference for its master's.
    pub fn follow(&self, master: Kinematics) -> Kinematics {
        Kinematics {
            pos: self.slave_origin + self.ratio * (master.pos - self.master_origin),
            vel: self.ratio * master.vel,
            acc: self.ratio * master.acc,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReferenceSource {
    Profile,
    Gear {
        master: u8,
        engaged: Option<Engagement>,
    },
    Homing(Homing),
    /// The commanded torque, per mille of rated torque.
    Torque {
        per_mille: f64,
    },
    Group {
        id: u8,
        synced: bool,
    },
}

impl ReferenceSource {
    /// Why the axis refuses its own motion (moves, `MoveHome`), if it does.
    pub fn refuses_motion(&self) -> Option<AxisError> {
        match self {
            ReferenceSource::Profile => None,
            ReferenceSource::Gear { .. } => Some(AxisError::CmdInvalidInSync),
            ReferenceSource::Homing(_) => Some(AxisError::CmdInvalidState),
            ReferenceSource::Torque { .. } => Some(AxisError::CmdInvalidControlMode),
            ReferenceSource::Group { .. } => Some(AxisError::CmdInvalidGrouped),
        }
    }

    /// The group the axis is in, if any.
    pub fn group(&self) -> Option<u8> {
        match self {
            ReferenceSource::Group { id, .. } => Some(*id),
            _ => None,
        }
    }

    /// `AddAxisToGrp` (HMPL 8.3.1): only an axis its own generator drives joins a group;
    /// it joins out of sync until the group is enabled.
    pub fn join_group(&mut self, id: u8) -> Result<(), AxisError> {
        match self {
            ReferenceSource::Profile => {
                *self = ReferenceSource::Group { id, synced: false };
                Ok(())
            }
            ReferenceSource::Group { .. } => Err(AxisError::CmdInvalidGrouped),
            other => Err(other.refuses_motion().unwrap_or(AxisError::CmdInvalidState)),
        }
    }

    /// `RemoveAxisFromGrp`, `UngrpAllAxes` (HMPL 8.3.2, 8.3.4): the generator again.
    pub fn leave_group(&mut self) {
        if self.group().is_some() {
            *self = ReferenceSource::Profile;
        }
    }

    /// The group takes the reference (`EnableGroup`, `ResetGroup`) or gives it back
    /// (`DisableGroup`, Group Error Stop).
    pub fn set_group_sync(&mut self, sync: bool) {
        if let ReferenceSource::Group { synced, .. } = self {
            *synced = sync;
        }
    }

    /// The group's interpolator gives the reference.
    pub fn is_group_synced(&self) -> bool {
        matches!(self, ReferenceSource::Group { synced: true, .. })
    }

    /// The master, if the axis is a gear slave.
    pub fn gear_master(&self) -> Option<u8> {
        match self {
            ReferenceSource::Gear { master, .. } => Some(*master),
            _ => None,
        }
    }

    /// The engaged gear, if the slave follows its master.
    pub fn engagement(&self) -> Option<Engagement> {
        match self {
            ReferenceSource::Gear { engaged, .. } => *engaged,
            _ => None,
        }
    }

    pub fn is_homing(&self) -> bool {
        matches!(self, ReferenceSource::Homing(_))
    }

    pub fn is_torque(&self) -> bool {
        matches!(self, ReferenceSource::Torque { .. })
    }

    /// `EnableGear` (HMPL 6.2): the axis becomes a slave of `master`, not yet engaged. A
    /// homing axis or one in torque mode cannot follow a master (docs/decisions.md,
    /// "Reference source").
    pub fn link_gear(&mut self, master: u8) -> Result<(), AxisError> {
        match self {
            ReferenceSource::Profile => {
                *self = ReferenceSource::Gear { master, engaged: None };
                Ok(())
            }
            ReferenceSource::Gear { .. } => Err(AxisError::CmdInvalidMasterSlaveConnection),
            ReferenceSource::Homing(_) => Err(AxisError::CmdInvalidState),
            ReferenceSource::Torque { .. } => Err(AxisError::CmdInvalidControlMode),
            ReferenceSource::Group { .. } => Err(AxisError::CmdInvalidGrouped),
        }
    }

    /// `DisableGear` (HMPL 6.3): the profile generator again. The link it was.
    pub fn unlink_gear(&mut self) -> Result<(u8, Option<Engagement>), AxisError> {
        match *self {
            ReferenceSource::Gear { master, engaged } => {
                *self = ReferenceSource::Profile;
                Ok((master, engaged))
            }
            _ => Err(AxisError::CmdGearDisabled),
        }
    }

    /// Whether `GearIn(master, ..)` may engage this axis (HMPL 6.4).
    pub fn may_engage(&self, master: u8) -> Result<(), AxisError> {
        match self {
            ReferenceSource::Gear { master: m, .. } if *m == master => Ok(()),
            ReferenceSource::Gear { .. } => Err(AxisError::CmdInvalidMasterSlaveConnection),
            _ => Err(AxisError::CmdGearDisabled),
        }
    }

    /// `GearIn` (HMPL 6.4): the slave follows `master` through `engagement`.
    pub fn engage(&mut self, master: u8, engagement: Engagement) -> Result<(), AxisError> {
        self.may_engage(master)?;
        *self = ReferenceSource::Gear { master, engaged: Some(engagement) };
        Ok(())
    }

    /// `GearOut` (HMPL 6.5), or a limit the master would take the slave past: linked, no
    /// longer following.
    pub fn disengage(&mut self) -> Result<(), AxisError> {
        match self {
            ReferenceSource::Gear { engaged: engaged @ Some(_), .. } => {
                *engaged = None;
                Ok(())
            }
            _ => Err(AxisError::CmdGearDisabled),
        }
    }

    /// `MoveHome` (HMPL 20.2): the drive's homing run drives the axis.
    pub fn start_homing(&mut self, homing: Homing) -> Result<(), AxisError> {
        if let Some(refused) = self.refuses_motion() {
            return Err(refused);
        }
        *self = ReferenceSource::Homing(homing);
        Ok(())
    }

    /// The homing run is over (done, failed or aborted): the profile generator again.
    pub fn end_homing(&mut self) {
        if self.is_homing() {
            *self = ReferenceSource::Profile;
        }
    }

    /// `SetOpMode` (HMPL 5.3.41): cst (`torque`) makes the torque the source, with no
    /// torque commanded yet; csp and csv the profile generator. A gear slave stays one
    /// in csp or csv but cannot take torque mode, and a homing run keeps the drive's mode
    /// (docs/decisions.md, "Reference source").
    pub fn set_torque_mode(&mut self, torque: bool) -> Result<(), AxisError> {
        match self {
            ReferenceSource::Profile | ReferenceSource::Torque { .. } => {
                *self = if torque { ReferenceSource::Torque { per_mille: 0.0 } } else { ReferenceSource::Profile };
                Ok(())
            }
            ReferenceSource::Gear { .. } if torque => Err(AxisError::CmdInvalidInSync),
            ReferenceSource::Gear { .. } => Ok(()),
            ReferenceSource::Homing(_) => Err(AxisError::CmdInvalidState),
            ReferenceSource::Group { .. } if torque => Err(AxisError::CmdInvalidGrouped),
            ReferenceSource::Group { .. } => Ok(()),
        }
    }

    /// `MoveTrq` (HMPL 5.2.7): a torque, per mille of rated, in torque mode only.
    pub fn command_torque(&mut self, per_mille: f64) -> Result<(), AxisError> {
        match self {
            ReferenceSource::Torque { per_mille: commanded } => {
                *commanded = per_mille;
                Ok(())
            }
            _ => Err(AxisError::CmdInvalidControlMode),
        }
    }

    /// `Stop` and its kin end a torque command: the torque falls to 0, the mode stays.
    pub fn stop_torque(&mut self) {
        if let ReferenceSource::Torque { per_mille } = self {
            *per_mille = 0.0;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use AxisError::*;
    use ReferenceSource::{Gear, Group, Profile, Torque};

    const E: Engagement = Engagement { ratio: 2.0, master_origin: 1.0, slave_origin: -3.0 };
    const MASTER: u8 = 4;

    /// A homing run that started in cycle 7.
    fn run() -> Homing {
        Homing::new(7)
    }

    fn homing() -> ReferenceSource {
        ReferenceSource::Homing(run())
    }

    fn linked() -> ReferenceSource {
        Gear { master: MASTER, engaged: None }
    }

    fn engaged() -> ReferenceSource {
        Gear { master: MASTER, engaged: Some(E) }
    }

    type Event = fn(&mut ReferenceSource) -> Result<(), AxisError>;

    /// (HMPL section, from, event, to or the error code).
    #[allow(clippy::type_complexity)]
    fn table() -> Vec<(&'static str, ReferenceSource, &'static str, Event, Result<ReferenceSource, AxisError>)> {
        vec![
            // Gear, HMPL 6.2 to 6.5.
            ("6.2", Profile, "EnableGear", |s| s.link_gear(MASTER), Ok(linked())),
            ("6.2", linked(), "EnableGear", |s| s.link_gear(MASTER), Err(CmdInvalidMasterSlaveConnection)),
            ("6.2", homing(), "EnableGear", |s| s.link_gear(MASTER), Err(CmdInvalidState)),
            ("6.2", Torque { per_mille: 0.0 }, "EnableGear", |s| s.link_gear(MASTER), Err(CmdInvalidControlMode)),
            ("6.4", linked(), "GearIn", |s| s.engage(MASTER, E), Ok(engaged())),
            ("6.4", linked(), "GearIn, other master", |s| s.engage(1, E), Err(CmdInvalidMasterSlaveConnection)),
            ("6.4", Profile, "GearIn", |s| s.engage(MASTER, E), Err(CmdGearDisabled)),
            ("6.4", homing(), "GearIn", |s| s.engage(MASTER, E), Err(CmdGearDisabled)),
            ("6.5", engaged(), "GearOut", ReferenceSource::disengage, Ok(linked())),
            ("6.5", linked(), "GearOut", ReferenceSource::disengage, Err(CmdGearDisabled)),
            ("6.5", Profile, "GearOut", ReferenceSource::disengage, Err(CmdGearDisabled)),
            ("6.3", linked(), "DisableGear", |s| s.unlink_gear().map(drop), Ok(Profile)),
            ("6.3", engaged(), "DisableGear", |s| s.unlink_gear().map(drop), Ok(Profile)),
            ("6.3", Profile, "DisableGear", |s| s.unlink_gear().map(drop), Err(CmdGearDisabled)),
            // Homing, HMPL 20.2.
            ("20.2", Profile, "MoveHome", |s| s.start_homing(run()), Ok(homing())),
            ("20.2", engaged(), "MoveHome", |s| s.start_homing(run()), Err(CmdInvalidInSync)),
            ("20.2", homing(), "MoveHome", |s| s.start_homing(run()), Err(CmdInvalidState)),
            ("20.2", Torque { per_mille: 0.0 }, "MoveHome", |s| s.start_homing(run()), Err(CmdInvalidControlMode)),
            (
                "20.2",
                homing(),
                "homing over",
                |s| {
                    s.end_homing();
                    Ok(())
                },
                Ok(Profile),
            ),
            // Groups, HMPL 8.3.1 to 8.3.4.
            ("8.3.1", Profile, "AddAxisToGrp", |s| s.join_group(2), Ok(Group { id: 2, synced: false })),
            ("8.3.1", Group { id: 1, synced: true }, "AddAxisToGrp", |s| s.join_group(2), Err(CmdInvalidGrouped)),
            ("8.3.1", engaged(), "AddAxisToGrp", |s| s.join_group(2), Err(CmdInvalidInSync)),
            ("8.3.1", homing(), "AddAxisToGrp", |s| s.join_group(2), Err(CmdInvalidState)),
            ("8.3.1", Torque { per_mille: 0.0 }, "AddAxisToGrp", |s| s.join_group(2), Err(CmdInvalidControlMode)),
            ("20.2", Group { id: 1, synced: false }, "MoveHome", |s| s.start_homing(run()), Err(CmdInvalidGrouped)),
            ("6.2", Group { id: 1, synced: false }, "EnableGear", |s| s.link_gear(MASTER), Err(CmdInvalidGrouped)),
            (
                "5.3.41",
                Group { id: 1, synced: true },
                "SetOpMode 10",
                |s| s.set_torque_mode(true),
                Err(CmdInvalidGrouped),
            ),
            // Operation mode and torque, HMPL 5.3.41 and 5.2.7.
            ("5.3.41", Profile, "SetOpMode 10", |s| s.set_torque_mode(true), Ok(Torque { per_mille: 0.0 })),
            (
                "5.3.41",
                Torque { per_mille: 300.0 },
                "SetOpMode 10",
                |s| s.set_torque_mode(true),
                Ok(Torque { per_mille: 0.0 }),
            ),
            ("5.3.41", Torque { per_mille: 300.0 }, "SetOpMode 8", |s| s.set_torque_mode(false), Ok(Profile)),
            ("5.3.41", engaged(), "SetOpMode 9", |s| s.set_torque_mode(false), Ok(engaged())),
            ("5.3.41", linked(), "SetOpMode 10", |s| s.set_torque_mode(true), Err(CmdInvalidInSync)),
            ("5.3.41", homing(), "SetOpMode 8", |s| s.set_torque_mode(false), Err(CmdInvalidState)),
            (
                "5.2.7",
                Torque { per_mille: 0.0 },
                "MoveTrq",
                |s| s.command_torque(250.0),
                Ok(Torque { per_mille: 250.0 }),
            ),
            ("5.2.7", Profile, "MoveTrq", |s| s.command_torque(250.0), Err(CmdInvalidControlMode)),
            (
                "5.2.9",
                Torque { per_mille: 250.0 },
                "Stop",
                |s| {
                    s.stop_torque();
                    Ok(())
                },
                Ok(Torque { per_mille: 0.0 }),
            ),
        ]
    }

    #[test]
    fn each_transition_goes_where_the_manual_says_or_is_refused_with_its_code() {
        for (section, from, event, apply, expected) in table() {
            let mut source = from;
            let result = apply(&mut source);
            match expected {
                Ok(to) => {
                    assert_eq!(result, Ok(()), "HMPL {section}: {from:?} --{event}--> refused");
                    assert_eq!(source, to, "HMPL {section}: {from:?} --{event}-->");
                }
                Err(code) => {
                    assert_eq!(result, Err(code), "HMPL {section}: {from:?} --{event}-->");
                    assert_eq!(source, from, "HMPL {section}: a refusal leaves the source as it was");
                }
            }
        }
    }

    #[test]
    fn own_motion_is_refused_by_every_source_but_the_profile() {
        assert_eq!(Profile.refuses_motion(), None, "HMPL 5.2");
        assert_eq!(engaged().refuses_motion(), Some(CmdInvalidInSync), "HMPL 6.2");
        assert_eq!(linked().refuses_motion(), Some(CmdInvalidInSync), "HMPL 6.2: linked, not engaged");
        assert_eq!(homing().refuses_motion(), Some(CmdInvalidState), "HMPL 20.2");
        assert_eq!(Torque { per_mille: 1.0 }.refuses_motion(), Some(CmdInvalidControlMode), "HMPL 5.3.41");
        assert_eq!(Group { id: 0, synced: true }.refuses_motion(), Some(CmdInvalidGrouped), "HMPL 8.1, 18.1.2.1");
    }

    #[test]
    fn an_engaged_slave_follows_its_master_scaled_from_the_engage_point() {
        // HMPL 6.1: the master moves 5 from where GearIn found it; the slave moves 10.
        let k = E.follow(Kinematics { pos: 6.0, vel: 100.0, acc: -50.0 });
        assert_eq!(k, Kinematics { pos: 7.0, vel: 200.0, acc: -100.0 });
    }
}
