//! HMPL ch. 10: a slave's analog channels. Conversion types and bindings are the
//! controller's (`crate::analog`); output words go into the slave's RxPDO (0x6411:nn),
//! where the kernel never writes. Codes (docs/decisions.md, "Slave analog I/O"): 0x138F no such
//! slave, channel or object in the process data, or a value out of range; 0x1388 no such
//! conversion type or variable; 0x138C no conversion type, or the output is bound.

use api::SystemError;
use api::analog::{ConversionType, split_var_id};
use schema::ANALOG_OUTPUTS;

use super::{Done, Failure, Outcome};
use crate::analog::Output;
use crate::machine::Machine;

fn out_of_range() -> Failure {
    SystemError::HmplArgOutOfRange.into()
}

fn not_ready() -> Failure {
    SystemError::HmplMotionNotReady.into()
}

/// Which way a channel goes.
#[derive(Clone, Copy)]
pub(super) enum Way {
    Input,
    Output,
}

/// Slave `slv_slot_id` (no slots here, so slot 0 only) and channel `idx` (1-based) of it:
/// the slave's index and the channel's position.
fn channel(m: &Machine, slv_slot_id: i64, idx: i64, way: Way) -> Result<(usize, usize), Failure> {
    let (id, slot) = api::constants::split_slave_slot(slv_slot_id);
    let slave =
        usize::try_from(id).ok().filter(|&s| slot == 0 && s < m.network.slaves().len()).ok_or_else(out_of_range)?;
    let (inputs, outputs) = m.network.slaves()[slave].device().analog_channels();
    let count = match way {
        Way::Input => inputs,
        Way::Output => outputs,
    };
    let n = usize::try_from(idx).ok().filter(|n| (1..=count as usize).contains(n)).ok_or_else(out_of_range)?;
    Ok((slave, n - 1))
}

fn output(m: &mut Machine, slave: usize, n: usize) -> &mut Output {
    &mut m.analog.slave_mut(slave).outputs[n]
}

/// HMPL 10.2.1, 10.2.2: a channel's conversion type; an output keeps a type while bound.
pub(super) fn set_type(m: &mut Machine, slv_slot_id: i64, idx: i64, range_type: i64, way: Way) -> Outcome {
    let (slave, n) = channel(m, slv_slot_id, idx, way)?;
    let ty = ConversionType::from_code(range_type).ok_or(SystemError::HmplInvalidArg)?;
    match way {
        Way::Input => m.analog.slave_mut(slave).inputs[n] = ty,
        Way::Output => {
            let output = output(m, slave, n);
            if output.bound && ty.range.bounds().is_none() {
                return Err(not_ready());
            }
            output.ty = ty;
        }
    }
    Ok(Done::Now)
}

/// HMPL 10.2.3, 10.2.4: an output's word into the RxPDO; not while the output is bound.
/// `word` gets the output's conversion type.
fn write_output(
    m: &mut Machine,
    slv_slot_id: i64,
    idx: i64,
    word: impl FnOnce(ConversionType) -> Result<u16, Failure>,
) -> Outcome {
    let (slave, n) = channel(m, slv_slot_id, idx, Way::Output)?;
    let field = m.network.output_field(slave, ANALOG_OUTPUTS, n as u8 + 1).ok_or_else(out_of_range)?;
    let output = *output(m, slave, n);
    if output.bound {
        return Err(not_ready());
    }
    let word = word(output.ty)?;
    field.write(m.network.images_mut().1, word as i16 as i64);
    Ok(Done::Now)
}

/// HMPL 10.2.3: any 16 bits, given as 0..65535 or -32768..32767.
pub(super) fn set_raw(m: &mut Machine, slv_slot_id: i64, idx: i64, raw: i64) -> Outcome {
    write_output(m, slv_slot_id, idx, |_| {
        (i16::MIN as i64..=u16::MAX as i64).contains(&raw).then_some(raw as u16).ok_or_else(out_of_range)
    })
}

/// HMPL 10.2.4: a value within the conversion type's range.
pub(super) fn set_value(m: &mut Machine, slv_slot_id: i64, idx: i64, value: f64) -> Outcome {
    write_output(m, slv_slot_id, idx, |ty| match ty.range.bounds() {
        None => Err(not_ready()),
        Some(_) => ty.word(value).ok_or_else(out_of_range),
    })
}

/// HMPL 10.4.1: the variable an output follows: an axis the machine has, and a conversion
/// type to put it in.
pub(super) fn set_monitor(m: &mut Machine, slv_slot_id: i64, idx: i64, var_id: i64) -> Outcome {
    let (slave, n) = channel(m, slv_slot_id, idx, Way::Output)?;
    let (axis, var) = split_var_id(var_id).ok_or(SystemError::HmplInvalidArg)?;
    if axis >= m.kernel.axes().len() {
        return Err(out_of_range());
    }
    let output = output(m, slave, n);
    if output.ty.range.bounds().is_none() {
        return Err(not_ready());
    }
    output.follow(var_id, axis, var);
    Ok(Done::Now)
}

/// HMPL 10.4.2: binds (1) or frees (0) an output with its scale and offset (finite: the
/// registry's range check); a binding needs its variable and the output in the process data.
pub(super) fn set_param(m: &mut Machine, slv_slot_id: i64, idx: i64, en_bind: i64, scale: f64, offset: f64) -> Outcome {
    let (slave, n) = channel(m, slv_slot_id, idx, Way::Output)?;
    if !(0..=1).contains(&en_bind) {
        return Err(out_of_range());
    }
    let bound = en_bind == 1;
    if bound && m.network.output_field(slave, ANALOG_OUTPUTS, n as u8 + 1).is_none() {
        return Err(out_of_range());
    }
    let output = output(m, slave, n);
    if bound && !output.follows() {
        return Err(not_ready());
    }
    output.bind(bound, scale, offset);
    Ok(Done::Now)
}

/// `SimSetSlvAIRaw`: the word on an analog terminal's input.
pub(super) fn sim_set_input(m: &mut Machine, slv_slot_id: i64, idx: i64, raw: i64) -> Outcome {
    let (slave, _) = channel(m, slv_slot_id, idx, Way::Input)?;
    m.network.set_analog_input(slave, idx, raw).map_err(|_| out_of_range())?;
    Ok(Done::Now)
}
