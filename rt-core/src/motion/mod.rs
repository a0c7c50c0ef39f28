//! The motion kernel: axes (HMPL ch. 5) computed once per cycle from the drives' inputs
//! and the commands of the cycle, never from the wall clock.

pub mod axis;
pub mod power;

use api::SystemError;
use ipc::messages::Snapshot;

use crate::config::MachineConfig;
use crate::ecat::Network;
use axis::{Axis, AxisIo};

pub struct Kernel {
    axes: Vec<Axis>,
}

impl Kernel {
    /// One axis per drive, in ring order, wired to the drive's mapped process data.
    pub fn new(config: &MachineConfig, network: &Network) -> Self {
        let period_s = config.period_ns() as f64 * 1e-9;
        let axes = config
            .axes
            .iter()
            .enumerate()
            .map(|(i, axis)| Axis::new(i as u8, axis, AxisIo::resolve(network, i), period_s))
            .collect();
        Kernel { axes }
    }

    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// The axis a script names, or HMPL's "argument out of range".
    pub fn axis_mut(&mut self, id: i64) -> Result<&mut Axis, SystemError> {
        usize::try_from(id).ok().and_then(|i| self.axes.get_mut(i)).ok_or(SystemError::HmplArgOutOfRange)
    }

    /// One cycle of every axis against the frame just exchanged.
    pub fn step(&mut self, cycle: u64, network: &mut Network) {
        let (inputs, outputs) = network.images_mut();
        for axis in &mut self.axes {
            axis.step(cycle, inputs, outputs);
        }
    }

    /// Disables every axis (controller shutdown, DisableAll).
    pub fn disable_all(&mut self) {
        for axis in &mut self.axes {
            let _ = axis.disable();
        }
    }

    pub fn fill(&self, snapshot: &mut Snapshot) {
        snapshot.axis_count = self.axes.len() as u32;
        for (slot, axis) in snapshot.axes.iter_mut().zip(&self.axes) {
            *slot = axis.snapshot();
        }
    }
}
