//! A simulated HIWIN CoE drive: the CiA 402 application of one EtherCAT slave.
//!
//! The drive sees only its object dictionary: the master writes the controlword and
//! targets (by PDO or SDO), the drive runs its state machine, its operation mode and its
//! servo loops, and writes the statusword and feedback objects back.

pub mod fsa;
pub mod od;
pub mod plant;

use serde::Deserialize;

use crate::cia402::{State, statusword};
use crate::config::AxisConfig;
use fsa::Fsa;
use od::ObjectStore;
use plant::{Demand, Plant, SERVO_PERIOD_S};

/// Drive families of the CoE manual, with their product codes (table 4-2).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum DriveModel {
    #[serde(rename = "D1-N")]
    D1N,
    D1,
    D2,
    #[serde(rename = "abily")]
    Abily,
}

impl DriveModel {
    pub fn product_code(self) -> u32 {
        match self {
            DriveModel::D1N => 1,
            DriveModel::D1 => 2,
            DriveModel::D2 => 3,
            DriveModel::Abily => 4,
        }
    }
}

/// Operation modes of 0x6060 (CoE manual table 4-17).
pub const MODE_CSP: i64 = 8;

pub struct Drive {
    model: DriveModel,
    od: ObjectStore,
    fsa: Fsa,
    plant: Plant,
    /// Position demand (counts) and its velocity, at the end of the last cycle.
    demand: f64,
    demand_velocity: f64,
}

impl Drive {
    pub fn new(axis: &AxisConfig) -> Self {
        Drive {
            model: axis.drive,
            od: ObjectStore::default(),
            fsa: Fsa::default(),
            plant: Plant::new(&axis.plant, axis.counts_per_unit),
            demand: 0.0,
            demand_velocity: 0.0,
        }
    }

    pub fn model(&self) -> DriveModel {
        self.model
    }

    pub fn od(&self) -> &ObjectStore {
        &self.od
    }

    pub fn od_mut(&mut self) -> &mut ObjectStore {
        &mut self.od
    }

    pub fn state(&self) -> State {
        self.fsa.state()
    }

    /// Sends the drive into Fault reaction active with a 0x603F error code.
    pub fn inject_fault(&mut self, error_code: u16) {
        self.od.set(od::ERROR_CODE, error_code as i64);
        self.fsa.fault();
    }

    /// One bus cycle of `period_s` seconds.
    pub fn step(&mut self, period_s: f64) {
        let stopped = self.demand_velocity == 0.0;
        self.fsa.step(self.od.get(od::CONTROLWORD) as u16, stopped);
        self.od.set(od::MODES_OF_OPERATION_DISPLAY, self.od.get(od::MODES_OF_OPERATION));

        let start = self.demand;
        let start_velocity = self.demand_velocity;
        let end = match self.fsa.state() {
            State::OperationEnabled => self.od.get(od::TARGET_POSITION) as f64,
            State::QuickStopActive | State::FaultReactionActive => self.ramp_down(period_s),
            _ => self.plant.position,
        };
        let energised = self.fsa.state().is_energised();
        let velocity = (end - start) / period_s;
        let acceleration = if energised { (velocity - start_velocity) / period_s } else { 0.0 };
        let substeps = (period_s / SERVO_PERIOD_S).round().max(1.0) as usize;
        for k in 1..=substeps {
            let demand = if energised {
                let position = start + (end - start) * k as f64 / substeps as f64;
                Demand::Position { position, velocity, acceleration }
            } else {
                Demand::Off
            };
            self.plant.step(demand);
        }
        self.demand = end;
        self.demand_velocity = if energised { velocity } else { 0.0 };
        self.update_feedback();
    }

    /// The quick-stop ramp: the demand decelerates with 0x6085 to rest.
    fn ramp_down(&mut self, period_s: f64) -> f64 {
        let dec = self.od.get(od::QUICK_STOP_DECELERATION) as f64;
        let v = self.demand_velocity;
        let dv = dec * period_s;
        let next_v = if v.abs() <= dv { 0.0 } else { v - dv * v.signum() };
        self.demand_velocity = next_v;
        self.demand + (v + next_v) / 2.0 * period_s
    }

    fn update_feedback(&mut self) {
        let actual = self.plant.encoder();
        let state = self.fsa.state();
        self.od.set(od::POSITION_ACTUAL, actual);
        self.od.set(od::POSITION_ACTUAL_INTERNAL, actual);
        self.od.set(od::VELOCITY_ACTUAL, self.plant.velocity.round() as i64);
        self.od.set(od::TORQUE_ACTUAL, (self.plant.force * 1000.0).round() as i64);
        self.od.set(od::POSITION_DEMAND_INTERNAL, self.demand.round() as i64);
        self.od.set(od::FOLLOWING_ERROR_ACTUAL, self.demand.round() as i64 - actual);
        let mut sw = state.statusword_bits() | statusword::REMOTE;
        if state.voltage_enabled() {
            sw |= statusword::VOLTAGE_ENABLED;
        }
        if state == State::OperationEnabled && self.od.get(od::MODES_OF_OPERATION_DISPLAY) == MODE_CSP {
            // CoE manual table 3-14: the target position is used as position-loop input.
            sw |= statusword::OMS_12;
        }
        self.od.set(od::STATUSWORD, sw as i64);
    }
}
