//! Alarms in the DXMC format (DXMC manual ch. 9, alarm code format): `0xXYZUABCD`, where
//! bit 31 is the level (0 error, 1 warning), bits 30..28 the source, `YZU` a 12-bit
//! extension (here the task or axis id) and `ABCD` the event code.

use std::fmt;

use num_enum::{FromPrimitive, IntoPrimitive};

/// DXMC alarm sources (bits 30..28).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Source {
    /// The controller as a whole.
    General = 0,
    /// The motion kernel; the extension is the axis id.
    MotionCore = 1,
    /// The PLC runtime (luamotion has none; kept for the format).
    PlcCore = 2,
    /// "RL core": the script runtime; the extension is the task id.
    RlCore = 3,
}

/// The events luamotion raises, with the DXMC event code each reuses (the `ABCD` of the
/// alarm code). Any other code is kept as an HMPL runtime error (`Hmpl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, FromPrimitive, IntoPrimitive)]
#[repr(u16)]
pub enum Event {
    /// Another task commanded an axis whose motion a task owns (DXMC 9: several programs
    /// command the same axis at the same time).
    CommandBufferBusy = 0x001F,
    /// A motion command while the controller is not in Run or Diagnosis.
    WrongMode = 0x0020,
    /// An invalid DRL control command (DXMC A.3, register 0x6B05).
    DrlControl = 0x7000,
    /// An unsupported PLC control command (DXMC A.3, register 0x6B10).
    PlcControl = 0x4105,
    /// The program ended with a Lua error.
    ProgramError = 0x4100,
    /// The task ran Lua past its watchdog time without reaching the controller.
    Watchdog = 0x4102,
    /// The task's process ran out of its memory limit.
    MemoryLimit = 0x4103,
    /// The task's process died of a signal (crash, `kill -9`).
    ProcessDied = 0x4104,
    /// The task's process did not start in time.
    StartTimeout = 0x1772,
    /// The EtherCAT segment stopped answering while running (DXMC manual ch. 9, event
    /// 0x6103 "EtherCAT disconnected"; remedy: the connection restarted).
    EtherCatDisconnected = 0x6103,
    /// An HMPL runtime error that stops a task, with its HMPL code (0x13EC: mutex locked twice).
    #[num_enum(catch_all)]
    Hmpl(u16),
}

impl Event {
    /// The event code, `ABCD` of the alarm.
    pub fn code(self) -> u16 {
        self.into()
    }

    /// What the event means, for the operator.
    pub fn meaning(self) -> &'static str {
        match self {
            Event::CommandBufferBusy => "command buffer busy: another task commanded an axis whose motion a task owns",
            Event::WrongMode => "the controller is not in Run or Diagnosis: motion commands are refused",
            Event::DrlControl => "DRL control command error: check the DRL control function code",
            Event::PlcControl => "unsupported PLC control command",
            Event::ProgramError => "the program stopped with an error",
            Event::Watchdog => "watchdog: the task ran past its watchdog time without reaching the controller",
            Event::MemoryLimit => "the task exceeded its memory limit",
            Event::ProcessDied => "the task's process died",
            Event::Hmpl(0x13EC) => "a mutex locked twice by the same task",
            Event::Hmpl(_) => "an HMPL runtime error",
            Event::StartTimeout => "the task's process did not start in time",
            Event::EtherCatDisconnected => "EtherCAT disconnected: the segment stopped answering in Op",
        }
    }
}

/// A 32-bit alarm code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Alarm(pub u32);

impl Alarm {
    /// An error-level alarm of `source` with extension `ext` (12 bits).
    pub fn error(source: Source, ext: u16, event: Event) -> Self {
        Alarm(((source as u32) << 28) | ((ext as u32 & 0xFFF) << 16) | event.code() as u32)
    }

    /// An alarm of the script runtime about task `task`.
    pub fn task(task: u8, event: Event) -> Self {
        Self::error(Source::RlCore, task as u16, event)
    }

    /// An alarm of the controller as a whole (the EtherCAT segment).
    pub fn general(event: Event) -> Self {
        Self::error(Source::General, 0, event)
    }

    /// Bits 30..28: the controller as a whole, not a task or an axis.
    pub fn is_general(self) -> bool {
        (self.0 >> 28) & 0x7 == Source::General as u32
    }

    /// An alarm of the motion core about axis `axis`.
    pub fn axis(axis: u8, event: Event) -> Self {
        Self::error(Source::MotionCore, axis as u16, event)
    }

    /// Bit 31: a warning rather than an error.
    pub fn is_warning(self) -> bool {
        self.0 & 0x8000_0000 != 0
    }

    /// `YZU`: the task or axis id the alarm is about.
    pub fn extension(self) -> u16 {
        ((self.0 >> 16) & 0xFFF) as u16
    }

    /// `ABCD`: the event code, see `Event`.
    pub fn event_code(self) -> u16 {
        self.0 as u16
    }
}

impl fmt::Display for Alarm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "0x{:08X}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// DXMC 9, alarm code format: the manual's examples and ours, as byte literals.
    #[test]
    fn layout() {
        let rows: [(Alarm, u32, &str); 6] = [
            (
                Alarm::error(Source::MotionCore, 1, Event::Hmpl(0x0815)),
                0x1001_0815,
                "DXMC example: axis 1, positive SW limit",
            ),
            (Alarm::task(2, Event::Watchdog), 0x3002_4102, "RL core, task 2, watchdog"),
            (Alarm::task(63, Event::Hmpl(0x13EC)), 0x303F_13EC, "RL core, task 63, mutex locked twice"),
            (Alarm::axis(0, Event::CommandBufferBusy), 0x1000_001F, "motion core, axis 0, 0x001F"),
            (Alarm::task(5, Event::ProcessDied), 0x3005_4104, "RL core, task 5, process died"),
            (Alarm::general(Event::EtherCatDisconnected), 0x0000_6103, "DXMC 9: general, EtherCAT disconnected"),
        ];
        for (alarm, literal, what) in rows {
            assert_eq!(alarm.0, literal, "{what}");
            assert!(!alarm.is_warning(), "{what}");
        }
        assert_eq!(Alarm(0x9001_0815).extension(), 1);
        assert!(Alarm(0x9001_0815).is_warning(), "DXMC example: the same as a warning");
        assert_eq!(Alarm::task(7, Event::Watchdog).to_string(), "0x30074102");
        for event in [Event::CommandBufferBusy, Event::Watchdog, Event::ProcessDied, Event::Hmpl(0x13EC)] {
            assert_eq!(Event::from(event.code()), event);
        }
    }
}
