//! HMPL ch. 10 on the controller's side: each slave's analog channels' conversion types
//! (table 10.1.1), which the controller keeps, and the outputs bound to an axis variable
//! (HMPL 10.4), written into the RxPDO every cycle as var * scale + offset. The words
//! themselves travel in process data (`analog_terminal.rs`); this holds no copy of them.

use api::analog::{AxisVariable, ConversionType};
use schema::{ANALOG_OUTPUTS, AnalogOutputSnapshot, AxisSnapshot, MAX_ANALOG_CHANNELS, MAX_SLAVES, Snapshot};

use devices::ecat::Network;

/// One analog output's settings.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Output {
    pub ty: ConversionType,
    /// `SetSlvAOMonitor`'s variable: its id as given and what it names (`follow`).
    var: Option<(i64, usize, AxisVariable)>,
    /// Set with `bind`, as the scale and offset.
    pub bound: bool,
    pub scale: f64,
    pub offset: f64,
    /// The variable's velocity a cycle ago, for `HMPL_ACC_FB` (NaN: none yet).
    last_vel: f64,
}

impl Default for Output {
    fn default() -> Self {
        let snapshot = AnalogOutputSnapshot::default();
        Output {
            ty: ConversionType::NONE,
            var: None,
            bound: false,
            scale: snapshot.scale,
            offset: snapshot.offset,
            last_vel: f64::NAN,
        }
    }
}

impl Output {
    /// Chooses the variable to follow (HMPL 10.4.1, `var_id` as given); the acceleration
    /// starts afresh.
    pub fn follow(&mut self, var_id: i64, axis: usize, var: AxisVariable) {
        (self.var, self.last_vel) = (Some((var_id, axis, var)), f64::NAN);
    }

    /// Binds or frees the output (HMPL 10.4.2); the acceleration starts afresh.
    pub fn bind(&mut self, bound: bool, scale: f64, offset: f64) {
        (self.bound, self.scale, self.offset, self.last_vel) = (bound, scale, offset, f64::NAN);
    }

    /// Whether a variable has been chosen.
    pub fn follows(&self) -> bool {
        self.var.is_some()
    }

    /// The `var_id` chosen, -1 before one is.
    pub fn var_id(&self) -> i64 {
        self.var.map_or(-1, |(id, ..)| id)
    }

    /// The bound variable's value this cycle, in the units its getter has (counts, A).
    fn variable(&mut self, axis: &AxisSnapshot, var: AxisVariable, period_s: f64) -> f64 {
        match var {
            AxisVariable::RefPos => axis.ref_pos,
            AxisVariable::RefVel => axis.ref_vel,
            AxisVariable::RefAcc => axis.ref_acc,
            AxisVariable::PosFb => axis.pos_fb,
            AxisVariable::VelFb => axis.vel_fb,
            AxisVariable::AccFb => {
                let last = std::mem::replace(&mut self.last_vel, axis.vel_fb);
                if last.is_nan() { 0.0 } else { (axis.vel_fb - last) / period_s }
            }
            AxisVariable::CurFb => axis.curr_fb,
        }
    }
}

/// One slave's analog channels, channel n at n - 1.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SlaveChannels {
    pub inputs: [ConversionType; MAX_ANALOG_CHANNELS],
    pub outputs: [Output; MAX_ANALOG_CHANNELS],
}

/// Every slave's analog settings, made once at start-up (the RT thread never allocates).
pub struct AnalogIo {
    slaves: Vec<SlaveChannels>,
}

impl Default for AnalogIo {
    fn default() -> Self {
        AnalogIo { slaves: vec![SlaveChannels::default(); MAX_SLAVES] }
    }
}

impl AnalogIo {
    pub(crate) fn slave_mut(&mut self, slave: usize) -> &mut SlaveChannels {
        &mut self.slaves[slave]
    }

    /// HMPL 10.4: each bound output's word from its variable this cycle, into the RxPDO
    /// after the kernel's stage (forced PDO values still win). A value past the range's
    /// ends saturates, as a converter does.
    pub fn step(&mut self, axes: &[AxisSnapshot], network: &mut Network, period_s: f64) {
        for (slave, channels) in self.slaves.iter_mut().enumerate().take(network.slaves().len()) {
            for (n, output) in channels.outputs.iter_mut().enumerate() {
                let Some((_, axis, var)) = output.var.filter(|_| output.bound) else { continue };
                let (Some(axis), Some(field)) =
                    (axes.get(axis), network.output_field(slave, ANALOG_OUTPUTS, n as u8 + 1))
                else {
                    continue;
                };
                let value = output.variable(axis, var, period_s) * output.scale + output.offset;
                field.write(network.images_mut().1, output.ty.word_clamped(value) as i16 as i64);
            }
        }
    }

    /// The settings into the snapshot's table of the slaves with analog channels.
    pub fn fill(&self, snapshot: &mut Snapshot) {
        for analog in snapshot.analog.iter_mut().filter(|a| a.input_count + a.output_count > 0) {
            let Some(channels) = self.slaves.get(analog.slave as usize) else { continue };
            for (code, ty) in analog.input_types.iter_mut().zip(&channels.inputs) {
                *code = ty.code() as u16;
            }
            for (out, o) in analog.outputs.iter_mut().zip(&channels.outputs) {
                *out = AnalogOutputSnapshot {
                    scale: o.scale,
                    offset: o.offset,
                    var_id: o.var_id() as i32,
                    range_type: o.ty.code() as u16,
                    bound: o.bound as u8,
                };
            }
        }
    }
}
