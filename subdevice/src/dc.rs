//! The distributed clock of one ESC (ETG.1000.4 6.8, tables 60 and 61) on a simulated
//! clock: a local time that runs with the segment's clock from the ESC's own power-up,
//! the receive times a write to 0x0900 latches, the system time (local time plus the
//! offset the master writes), its comparison with the reference clock the master
//! distributes, and the SYNC0 unit.
//!
//! The simulated clocks do not drift, so the control loop only has the initial phase
//! error to remove; it removes at most `MAX_CORRECTION_NS` per compare
//! (docs/decisions.md, "DC control loop").

use crate::registers::{
    DC_ACTIVATION, DC_ACTIVATION_STATUS, DC_RECEIVE_TIME_PORT0, DC_RECEIVE_TIME_PU, DC_START_TIME, DC_SYNC0_CYCLE,
    DC_SYNC0_STATUS, DC_SYSTEM_TIME, DC_SYSTEM_TIME_DELAY, DC_SYSTEM_TIME_DIFFERENCE, DC_SYSTEM_TIME_OFFSET, Registers,
};

/// The most one compare moves the system time.
pub const MAX_CORRECTION_NS: i64 = 1_000;
/// Activation bits (0x0981): cyclic operation and SYNC0.
const CYCLIC_OPERATION: u8 = 0b01;
const SYNC0: u8 = 0b10;
/// 0x0984 bit 0: SYNC0 armed, first pulse pending; bit 2: start time out of range.
const FIRST_PULSE_PENDING: u8 = 0b001;
const START_OUT_OF_RANGE: u8 = 0b100;
/// 0x092C bit 31: the local copy of the system time is smaller than the received one.
const LOCAL_SMALLER: u32 = 1 << 31;

/// Where the SYNC0 unit is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sync0 {
    Off,
    /// The next pulse, in system time; `cycle_ns` 0 is a single shot.
    Armed {
        next: u64,
        cycle_ns: u32,
        pulsed: bool,
    },
}

/// SYNC0 pulses that passed, and the cycle between them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pulses {
    /// Pulses since the last look, at most the cap asked for.
    pub count: u32,
    /// SYNC0 cycle time, ns.
    pub cycle_ns: u32,
}

/// One ESC's clock.
#[derive(Clone, Debug)]
pub struct DistributedClock {
    /// Local time = segment clock + this: each ESC powered up at its own moment.
    boot_ns: u64,
    sync0: Sync0,
    /// A pulse since the last read of the SYNC0 status.
    pulse_seen: bool,
}

impl DistributedClock {
    /// A clock whose local time is `boot_ns` ahead of the segment's clock.
    pub fn new(boot_ns: u64) -> Self {
        DistributedClock { boot_ns, sync0: Sync0::Off, pulse_seen: false }
    }

    /// Local time at segment time `now`.
    pub fn local_time(&self, now: u64) -> u64 {
        now.wrapping_add(self.boot_ns)
    }

    /// System time at `now`: local time plus the offset register.
    pub fn system_time(&self, registers: &Registers, now: u64) -> u64 {
        self.local_time(now).wrapping_add(registers.u64(DC_SYSTEM_TIME_OFFSET))
    }

    /// A write to 0x0900: every port's receive time of this frame is latched (32 bits of
    /// local time each; a closed port keeps 0), and the processing unit's (64 bits).
    pub fn latch(&self, registers: &mut Registers, ports: [Option<u64>; 4], processing_unit: u64) {
        for (port, time) in ports.iter().enumerate() {
            let value = time.map_or(0, |t| self.local_time(t) as u32);
            registers.set_u32(DC_RECEIVE_TIME_PORT0 + 4 * port as u16, value);
        }
        registers.set_u64(DC_RECEIVE_TIME_PU, self.local_time(processing_unit));
    }

    /// A write of `width` bytes (4 or 8) to 0x0910 arriving at `now`: the received time
    /// plus the delay register is compared with the own system time, the difference goes
    /// to 0x092C and the loop moves the offset towards it.
    pub fn compare(&self, registers: &mut Registers, received: u64, width: usize, now: u64) {
        let own = self.system_time(registers, now);
        let reference = received.wrapping_add(u64::from(registers.u32(DC_SYSTEM_TIME_DELAY)));
        let difference = if width >= 8 {
            reference.wrapping_sub(own) as i64
        } else {
            i64::from((reference as u32).wrapping_sub(own as u32) as i32)
        };
        let magnitude = difference.unsigned_abs().min(u64::from(!LOCAL_SMALLER)) as u32;
        registers.set_u32(DC_SYSTEM_TIME_DIFFERENCE, magnitude | if difference > 0 { LOCAL_SMALLER } else { 0 });
        let step = difference.clamp(-MAX_CORRECTION_NS, MAX_CORRECTION_NS);
        let offset = registers.u64(DC_SYSTEM_TIME_OFFSET).wrapping_add_signed(step);
        registers.set_u64(DC_SYSTEM_TIME_OFFSET, offset);
    }

    /// The activation register was written: with cyclic operation and SYNC0 on, the unit
    /// arms at the start time written to 0x0990, unless that lies in the past (a 64-bit
    /// ESC would wait for ever: it reports the start time out of range instead).
    pub fn activate(&mut self, registers: &mut Registers, now: u64) {
        let activation = registers.byte(DC_ACTIVATION);
        let mut status = 0;
        self.sync0 = Sync0::Off;
        if activation & (CYCLIC_OPERATION | SYNC0) == CYCLIC_OPERATION | SYNC0 {
            let start = registers.u64(DC_START_TIME);
            if start < self.system_time(registers, now) {
                status = START_OUT_OF_RANGE;
            } else {
                let cycle_ns = registers.u32(DC_SYNC0_CYCLE);
                self.sync0 = Sync0::Armed { next: start, cycle_ns, pulsed: false };
                status = FIRST_PULSE_PENDING;
            }
        }
        registers.set_byte(DC_ACTIVATION_STATUS, status);
    }

    /// The SYNC0 cycle when SYNC0 runs cyclically (a single shot does not clock a drive).
    pub fn cycle_ns(&self) -> Option<u32> {
        match self.sync0 {
            Sync0::Armed { cycle_ns, .. } if cycle_ns > 0 => Some(cycle_ns),
            _ => None,
        }
    }

    /// The SYNC0 pulses up to `now`, at most `cap`: a longer gap skips the pulses beyond
    /// it, so that the next look starts from the present.
    pub fn pulses(&mut self, registers: &mut Registers, now: u64, cap: u32) -> Pulses {
        let system = self.system_time(registers, now);
        let Sync0::Armed { next, cycle_ns, pulsed } = &mut self.sync0 else {
            return Pulses { count: 0, cycle_ns: 0 };
        };
        if *next > system {
            return Pulses { count: 0, cycle_ns: *cycle_ns };
        }
        let cycle = *cycle_ns;
        if cycle == 0 {
            self.sync0 = Sync0::Off;
            self.pulse_seen = true;
            registers.set_byte(DC_ACTIVATION_STATUS, 0);
            return Pulses { count: 1, cycle_ns: 0 };
        }
        let passed = (system - *next) / u64::from(cycle) + 1;
        *next = next.saturating_add(passed.saturating_mul(u64::from(cycle)));
        *pulsed = true;
        self.pulse_seen = true;
        registers.set_byte(DC_ACTIVATION_STATUS, 0);
        Pulses { count: passed.min(u64::from(cap)) as u32, cycle_ns: cycle }
    }

    /// Writes the registers that run with the clock before a read at `now`: the system
    /// time, the next SYNC0 pulse, the SYNC0 status.
    pub fn render(&self, registers: &mut Registers, now: u64) {
        registers.set_u64(DC_SYSTEM_TIME, self.system_time(registers, now));
        if let Sync0::Armed { next, pulsed: true, .. } = self.sync0 {
            registers.set_u64(DC_START_TIME, next);
        }
        registers.set_byte(DC_SYNC0_STATUS, u8::from(self.pulse_seen));
    }

    /// The SYNC0 status was read: it is acknowledged.
    pub fn acknowledge(&mut self) {
        self.pulse_seen = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn system_time_is_local_time_plus_the_offset() {
        let mut registers = Registers::default();
        let clock = DistributedClock::new(5_000);
        assert_eq!(clock.local_time(100), 5_100);
        registers.set_u64(DC_SYSTEM_TIME_OFFSET, (-5_100i64) as u64);
        assert_eq!(clock.system_time(&registers, 100), 0);
        clock.render(&mut registers, 1_100);
        assert_eq!(registers.u64(DC_SYSTEM_TIME), 1_000);
    }

    #[test]
    fn a_latch_keeps_each_port_s_receive_time() {
        let mut registers = Registers::default();
        let clock = DistributedClock::new(0x1_0000_0010);
        clock.latch(&mut registers, [Some(100), Some(900), None, None], 100);
        assert_eq!(registers.u32(DC_RECEIVE_TIME_PORT0), 0x74, "32 bits of local time");
        assert_eq!(registers.u32(DC_RECEIVE_TIME_PORT0 + 4), 0x394);
        assert_eq!(registers.u32(DC_RECEIVE_TIME_PORT0 + 8), 0);
        assert_eq!(registers.u64(DC_RECEIVE_TIME_PU), 0x1_0000_0074);
    }

    /// The reference is 600 ns ahead: 0x092C says so, the offset moves by it.
    #[test]
    fn a_compare_shows_the_difference_and_closes_it() {
        let mut registers = Registers::default();
        let clock = DistributedClock::new(0);
        registers.set_u32(DC_SYSTEM_TIME_DELAY, 100);
        clock.compare(&mut registers, 1_500, 8, 1_000);
        assert_eq!(registers.u32(DC_SYSTEM_TIME_DIFFERENCE), LOCAL_SMALLER | 600);
        assert_eq!(clock.system_time(&registers, 1_000), 1_600);
        clock.compare(&mut registers, 0, 4, 10_000_000);
        assert_eq!(registers.u32(DC_SYSTEM_TIME_DIFFERENCE), 10_000_000 + 600 - 100);
        assert_eq!(clock.system_time(&registers, 10_000_000), 10_000_600 - MAX_CORRECTION_NS as u64);
    }

    /// SOEM's `dcsync0`: start time in the future, cycle 1 ms; the pulses come one per ms.
    #[test]
    fn sync0_pulses_from_the_start_time_at_the_cycle() {
        let mut registers = Registers::default();
        let mut clock = DistributedClock::new(0);
        registers.set_u64(DC_START_TIME, 2_000_000);
        registers.set_u32(DC_SYNC0_CYCLE, 1_000_000);
        registers.set_byte(DC_ACTIVATION, 0b11);
        clock.activate(&mut registers, 0);
        assert_eq!(clock.cycle_ns(), Some(1_000_000));
        assert_eq!(registers.byte(DC_ACTIVATION_STATUS), FIRST_PULSE_PENDING);
        assert_eq!(clock.pulses(&mut registers, 1_999_999, 100).count, 0);
        assert_eq!(clock.pulses(&mut registers, 2_000_000, 100), Pulses { count: 1, cycle_ns: 1_000_000 });
        assert_eq!(clock.pulses(&mut registers, 4_500_000, 100).count, 2);
        assert_eq!(clock.pulses(&mut registers, 1_000_000_000, 100).count, 100, "capped");
        assert_eq!(clock.pulses(&mut registers, 1_000_999_999, 100).count, 0, "from the present on");
        assert_eq!(clock.pulses(&mut registers, 1_001_000_000, 100).count, 1);
        clock.render(&mut registers, 1_001_000_000);
        assert_eq!(registers.u64(DC_START_TIME), 1_002_000_000, "0x0990 reads the next pulse");
        assert_eq!(registers.byte(DC_SYNC0_STATUS), 1);
        clock.acknowledge();
        clock.render(&mut registers, 1_001_000_000);
        assert_eq!(registers.byte(DC_SYNC0_STATUS), 0);
    }

    #[test]
    fn a_start_time_in_the_past_never_fires() {
        let mut registers = Registers::default();
        let mut clock = DistributedClock::new(0);
        registers.set_u64(DC_START_TIME, 10);
        registers.set_byte(DC_ACTIVATION, 0b11);
        clock.activate(&mut registers, 1_000);
        assert_eq!(clock.cycle_ns(), None);
        assert_eq!(registers.byte(DC_ACTIVATION_STATUS), START_OUT_OF_RANGE);
        assert_eq!(clock.pulses(&mut registers, 2_000_000, 10).count, 0);
    }
}
