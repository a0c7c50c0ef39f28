//! Drive faults: the 0x603F error codes of CoE manual table 4-16, the models that report
//! them, and their bits in the error events 0x2100 (table 4-13) and 0x2101 (table 4-14).

use crate::drive::DriveModel;

/// Which error-events object carries a fault's bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Events {
    /// Drive error events 1, 0x2100 (table 4-13).
    One,
    /// Drive error events 2, 0x2101 (table 4-14).
    Two,
}

/// One row of table 4-16: code, description, events bit, support on D1COE, D2COE, D1NCOE.
pub struct FaultDef {
    /// The error code the drive writes to 0x603F.
    pub code: u16,
    /// The description as table 4-16 prints it.
    pub description: &'static str,
    /// The error-events object its bit is in.
    pub events: Events,
    /// Its bit in that object (inferred from the names of tables 4-13 and 4-14).
    pub bit: u8,
    /// Reported by D1COE (and abily).
    pub d1: bool,
    /// Reported by D2COE.
    pub d2: bool,
    /// Reported by D1NCOE.
    pub d1n: bool,
}

const fn f(code: u16, description: &'static str, events: Events, bit: u8, d1: bool, d2: bool, d1n: bool) -> FaultDef {
    FaultDef { code, description, events, bit, d1, d2, d1n }
}

use Events::{One, Two};

/// Table 4-16 in the manual's order (its numbers 16 and 21 do not exist).
pub static FAULTS: &[FaultDef] = &[
    f(0x2310, "Motor short (over current)", One, 18, true, true, true),
    f(0x3110, "Over voltage", One, 19, true, true, true),
    f(0x8611, "Position error too big", One, 6, true, true, true),
    f(0x7380, "Encoder error", One, 1, true, true, true),
    f(0x2350, "Soft-thermal threshold reached", One, 7, true, true, true),
    f(0x7180, "Motor maybe disconnected", One, 21, true, true, true),
    f(0x4310, "Amplifier over temperature", One, 15, true, true, true),
    f(0x7383, "Motor over temperature", One, 14, true, false, true),
    f(0x3220, "Under voltage", One, 20, true, true, true),
    f(0x5280, "5V for encoder card fail", One, 31, true, true, true),
    f(0xFF06, "Phase initialization error", Two, 1, true, true, true),
    f(0x7381, "Serial encoder communication error", One, 13, true, true, true),
    f(0x7382, "Hall sensor error", Two, 5, true, true, true),
    f(0x7384, "Hall phase check error", Two, 6, true, false, true),
    f(0xFF02, "Current control error", Two, 16, true, true, true),
    f(0x86FF, "Hybrid deviation too big", Two, 20, false, true, true),
    f(0xFF03, "STO active", Two, 7, false, true, true),
    // HFLT: 0x2100 bit 9 on D1-N, 0x2101 bit 17 on D1 and D2 (`events_bit` picks).
    f(0xFF04, "HFLT inconsistent error", Two, 17, true, true, true),
    f(0xFF05, "Auto phase center not complete yet", Two, 18, true, false, true),
    f(0x3210, "DC bus voltage abnormal", Two, 23, true, true, true),
    f(0x7580, "EtherCAT interface is not detected", Two, 30, true, true, true),
    f(0x8613, "CiA-402 homing error", Two, 31, true, true, true),
    f(0x5180, "Fan fault error", Two, 25, false, true, false),
];

/// 0x603F for a following error beyond 0x6065 for longer than 0x6066 (CoE manual 3.3.2).
pub const POSITION_ERROR_TOO_BIG: u16 = 0x8611;
/// 0x603F for a failed homing, "CiA-402 Homing error" (CoE manual 3.2).
pub const HOMING_ERROR: u16 = 0x8613;

impl FaultDef {
    /// Table 4-16 lists D1COE, D2COE and D1NCOE; abily follows D1COE (docs/drive.md).
    pub fn supported_on(&self, model: DriveModel) -> bool {
        match model {
            DriveModel::D1 | DriveModel::Abily => self.d1,
            DriveModel::D2 => self.d2,
            DriveModel::D1N => self.d1n,
        }
    }

    /// The events object and bit this fault sets on `model`.
    pub fn events_bit(&self, model: DriveModel) -> (Events, u8) {
        if self.code == 0xFF04 && model == DriveModel::D1N { (One, 9) } else { (self.events, self.bit) }
    }
}

/// The row of 0x603F code `code`, `None` for a code table 4-16 does not list.
pub fn find(code: u16) -> Option<&'static FaultDef> {
    FAULTS.iter().find(|f| f.code == code)
}
