//! The machine at the end of one cycle: what every status query reads.

use crate::axis::AxisSnapshot;
use crate::group::GroupSnapshot;
use crate::ids::{MAX_AXES, MAX_GROUPS, MAX_TASKS};
use crate::slave::{AnalogSnapshot, MAX_ANALOG_TERMINALS, MAX_SLAVES, SlaveSnapshot};
use crate::task::TaskSnapshot;

/// HMPL 9.1: the controller has 8 inputs and 8 outputs, pins 1..8.
pub const GPIO_PINS: i64 = 8;

/// The controller's own digital I/O (HMPL ch. 9): bit i is pin i + 1.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct GpioSnapshot {
    /// Inputs as programs read them (after inversion).
    pub gpi: u32,
    /// Outputs as the controller drives them.
    pub gpo: u32,
    /// The inversion mask of the inputs (HMPL 9.5).
    pub gpi_invert: u32,
    /// The inversion mask of the outputs (HMPL 9.5).
    pub gpo_invert: u32,
    /// The input bound to the E-stop (1-based; 0: none).
    pub emo_input: u32,
}

/// The machine at the end of one cycle, published every cycle (latest value wins).
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub struct Snapshot {
    /// `system_fclk`: cycles since start.
    pub cycle: u64,
    /// The cycle period, ns.
    pub period_ns: u64,
    /// `system_timeInMs`: controller time, derived from the cycle count.
    pub time_in_ms: u64,
    /// CLOCK_MONOTONIC at publication, for the age of a snapshot when read.
    pub published_ns: u64,
    /// Axes in use (of `MAX_AXES`).
    pub axis_count: u32,
    /// EtherCAT master state: 1 Init, 2 PreOp, 4 SafeOp, 8 Op (HMPL 2.5).
    pub ecat_state: u32,
    /// The system is in error (HMPL 2.4): EtherCAT start-up stopped short of Op.
    pub system_error: u32,
    /// The last system error code (HMPL 18.2).
    pub system_last_err: u32,
    /// Slaves on the segment (of `MAX_SLAVES`).
    pub slave_count: u32,
    /// Each group's last error (HMPL 18.5).
    pub group_last_err: [u32; MAX_GROUPS],
    /// Every group (HMPL ch. 8).
    pub groups: [GroupSnapshot; MAX_GROUPS],
    /// Cycles whose work ran past the next deadline, since start.
    pub overruns: u64,
    /// DXMC 3.6, register 0x6A80: 0 Initial, 1 Fail, 2 Edit, 4 Run, 5 Diagnosis.
    pub controller_state: u32,
    /// The controller's digital I/O.
    pub gpio: GpioSnapshot,
    /// Every task's slot.
    pub tasks: [TaskSnapshot; MAX_TASKS],
    /// Every axis, the first `axis_count` in use.
    pub axes: [AxisSnapshot; MAX_AXES],
    /// Every slave, the first `slave_count` present.
    pub slaves: [SlaveSnapshot; MAX_SLAVES],
    /// The slaves with analog channels, in bus order; an entry without channels is free.
    pub analog: [AnalogSnapshot; MAX_ANALOG_TERMINALS],
    /// Every axis' position trigger (HMPL ch. 12).
    pub position_triggers: [PtSnapshot; MAX_AXES],
    /// The process data frames on a wire (`[bus] interface`); zero in memory.
    pub wire: WireSnapshot,
}

/// What the process data on a wire did since start-up, as `luamotion tasks` reports it.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct WireSnapshot {
    /// 1 when the segment is on a wire.
    pub on_wire: u64,
    /// Cycles whose frame came back complete.
    pub good: u64,
    /// Cycles without a frame back (lost, late, the cable).
    pub missing: u64,
    /// Frames back short of the working counter (a slave did not take part).
    pub short: u64,
    /// Frames back that matched nothing sent (duplicated on the way, or late).
    pub unmatched: u64,
}

/// An axis' position trigger (HMPL ch. 12), its last pass.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub struct PtSnapshot {
    /// 1 while a pass runs (HMPL 12.4).
    pub enabled: u32,
    /// Pulses given in the pass.
    pub pulses: u32,
    /// Points reached in the same drive sample as the pulse before: no pulse for them.
    pub missed: u32,
}

impl Default for Snapshot {
    fn default() -> Self {
        Snapshot {
            cycle: 0,
            period_ns: 0,
            time_in_ms: 0,
            published_ns: 0,
            axis_count: 0,
            ecat_state: 0,
            system_error: 0,
            system_last_err: 0,
            slave_count: 0,
            group_last_err: [0; MAX_GROUPS],
            groups: [GroupSnapshot::default(); MAX_GROUPS],
            overruns: 0,
            controller_state: 0,
            gpio: GpioSnapshot::default(),
            tasks: [TaskSnapshot::default(); MAX_TASKS],
            axes: [AxisSnapshot::default(); MAX_AXES],
            slaves: [SlaveSnapshot::default(); MAX_SLAVES],
            position_triggers: [PtSnapshot::default(); MAX_AXES],
            analog: [AnalogSnapshot::default(); MAX_ANALOG_TERMINALS],
            wire: WireSnapshot::default(),
        }
    }
}

impl Snapshot {
    /// Slave `slave`'s analog channels, if it has any (HMPL ch. 10).
    pub fn analog_of(&self, slave: usize) -> Option<&AnalogSnapshot> {
        self.analog.iter().find(|a| a.slave as usize == slave && a.input_count + a.output_count > 0)
    }
}

// SAFETY: repr(C), plain numbers and arrays of them, all valid when zeroed.
unsafe impl crate::layout::Plain for Snapshot {}
