//! HMPL ch. 9: the controller's digital I/O, and the slaves' digital outputs (9.3) written
//! into their process data.

use schema::{SLAVE_DIGITAL_OUTPUTS, channel_mask};

use super::{Done, Failure, Outcome, drive_objects::out_of_range};
use crate::io::NoSuchPin;
use crate::machine::Machine;

/// Ch. 9: 0, or -1 for a pin that does not exist.
pub(super) fn pin(result: Result<(), NoSuchPin>) -> Outcome {
    result.map(|()| Done::Now).map_err(|_| out_of_range())
}

/// HMPL 9.1: slave `slv_id | HMPL_SLOT_n`; slaves here have no slots, so only slot 0.
fn slave_index(m: &Machine, slv_slot_id: i64) -> Result<usize, Failure> {
    let (id, slot) = api::constants::split_slave_slot(slv_slot_id);
    let slave = usize::try_from(id).map_err(|_| out_of_range())?;
    if slot != 0 || slave >= m.network.slaves().len() {
        return Err(out_of_range());
    }
    Ok(slave)
}

/// HMPL 9.3: changes a slave's output channels in the master's RxPDO image, where the kernel
/// never writes, so they hold until changed. `change` gets the channels (bit 0 = output 1)
/// and their mask and returns the new channels. -1 when the slave has no outputs in its
/// process data (e.g. a drive without 0x60FE:01 mapped).
pub(super) fn change_slave_outputs(
    m: &mut Machine,
    slv_slot_id: i64,
    change: impl FnOnce(u32, u32) -> Result<u32, Failure>,
) -> Outcome {
    let slave = slave_index(m, slv_slot_id)?;
    let mask = channel_mask(m.network.slaves()[slave].device().digital_channels().1);
    let (field, word) = SLAVE_DIGITAL_OUTPUTS
        .iter()
        .find_map(|w| Some((m.network.output_field(slave, w.index, w.sub)?, w)))
        .ok_or_else(out_of_range)?;
    if mask == 0 {
        return Err(out_of_range());
    }
    let (_, outputs) = m.network.images_mut();
    let raw = field.read(outputs) as u64;
    let shifted = (mask as u64) << word.first_bit;
    let channels = change(((raw & shifted) >> word.first_bit) as u32, mask)?;
    let raw = (raw & !shifted) | ((channels as u64 & mask as u64) << word.first_bit);
    field.write(outputs, raw as i64);
    Ok(Done::Now)
}

/// Output channel `pin`'s bit among `mask`'s channels.
pub(super) fn channel_bit(pin: i64, mask: u32) -> Result<u32, Failure> {
    let bit = pin.checked_sub(1).and_then(|b| u32::try_from(b).ok()).filter(|&b| b < 32).map(|b| 1u32 << b);
    bit.filter(|&b| b & mask != 0).ok_or_else(out_of_range)
}

/// `SetSlvAllGPO`'s bitmask: only channels the slave has.
pub(super) fn all_channels(state: i64, mask: u32) -> Result<u32, Failure> {
    u32::try_from(state).ok().filter(|&s| s & !mask == 0).ok_or_else(out_of_range)
}

/// `SimSetSlvGPI`: a terminal's input switch.
pub(super) fn sim_set_slave_input(m: &mut Machine, slv_slot_id: i64, pin: i64, on_off: i64) -> Outcome {
    let slave = slave_index(m, slv_slot_id)?;
    m.network.set_terminal_input(slave, pin, on_off != 0).map_err(|_| out_of_range())?;
    Ok(Done::Now)
}
