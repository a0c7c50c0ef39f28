//! The master's services beside the motion kernel: forced process-data values (HMPL
//! 17.2.8/17.2.9) and what the snapshot shows of each slave.

use schema::{
    AnalogSnapshot, MAX_ANALOG_TERMINALS, MAX_PDO_BYTES, MAX_PDO_ENTRIES, PdoEntrySnapshot, SlaveSnapshot, Snapshot,
    WireSnapshot,
};

use devices::ecat::network::ImageEntry;
use devices::ecat::{Field, Network, WireCounters};

/// How many objects may be forced at once.
pub const MAX_FORCES: usize = 32;

/// Forced RxPDO values: written after the kernel every cycle, so they win over it.
#[derive(Clone, Debug, Default)]
pub struct PdoForces {
    slots: [Option<(Field, i64)>; MAX_FORCES],
}

impl PdoForces {
    /// Forces a field; false when every slot is taken.
    pub fn force(&mut self, field: Field, value: i64) -> bool {
        if let Some(slot) = self.slots.iter_mut().flatten().find(|(f, _)| *f == field) {
            slot.1 = value;
            return true;
        }
        match self.slots.iter_mut().find(|s| s.is_none()) {
            Some(slot) => {
                *slot = Some((field, value));
                true
            }
            None => false,
        }
    }

    /// Releases a field; false when it was not forced.
    pub fn release(&mut self, field: Field) -> bool {
        match self.slots.iter_mut().find(|s| s.is_some_and(|(f, _)| f == field)) {
            Some(slot) => {
                *slot = None;
                true
            }
            None => false,
        }
    }

    pub(crate) fn apply(&self, outputs: &mut [u8]) {
        for (field, value) in self.slots.iter().flatten() {
            field.write(outputs, *value);
        }
    }
}

fn entries(mapping: &[ImageEntry]) -> ([PdoEntrySnapshot; MAX_PDO_ENTRIES], u8) {
    let mut entries = [PdoEntrySnapshot::default(); MAX_PDO_ENTRIES];
    for (entry, m) in entries.iter_mut().zip(mapping) {
        *entry = PdoEntrySnapshot {
            index: m.index,
            sub: m.sub,
            bits: m.ty.bits(),
            offset: m.offset as u8,
            signed: m.ty.is_signed() as u8,
        };
    }
    (entries, mapping.len().min(MAX_PDO_ENTRIES) as u8)
}

/// What does not change after start-up: slave count, the mappings as the master laid
/// them out, channels.
pub fn describe_slaves(network: &Network, snapshot: &mut Snapshot) {
    snapshot.slave_count = network.slaves().len() as u32;
    for (i, (slot, slave)) in snapshot.slaves.iter_mut().zip(network.slaves()).enumerate() {
        let (rx, tx) = network.image_entries(i);
        let ((rx, rx_count), (tx, tx_count)) = (entries(rx), entries(tx));
        let (digital_inputs, digital_outputs) = slave.device().digital_channels();
        *slot =
            SlaveSnapshot { rx, rx_count, tx, tx_count, digital_inputs, digital_outputs, ..SlaveSnapshot::default() };
    }
    // The machine file allows no more analog terminals than the table holds.
    let analog = network.slaves().iter().enumerate().filter_map(|(i, slave)| {
        let (input_count, output_count) = slave.device().analog_channels();
        let slave = i as u16;
        (input_count + output_count > 0).then_some(AnalogSnapshot {
            slave,
            input_count,
            output_count,
            ..AnalogSnapshot::default()
        })
    });
    snapshot.analog = [AnalogSnapshot::default(); MAX_ANALOG_TERMINALS];
    for (slot, entry) in snapshot.analog.iter_mut().zip(analog) {
        *slot = entry;
    }
}

/// What changes every cycle: AL states, the process data, and on a wire its frames.
pub fn update_slaves(network: &Network, snapshot: &mut Snapshot) {
    snapshot.ecat_state = network.state().code() as u32;
    if let Some(counters) = network.wire_counters() {
        let WireCounters { good, missing, short, unmatched, .. } = counters;
        snapshot.wire = WireSnapshot { on_wire: 1, good, missing, short, unmatched };
    }
    for (i, (slot, slave)) in snapshot.slaves.iter_mut().zip(network.slaves()).enumerate() {
        // On a wire the master knows the segment's lowest state, not each slave's code.
        let (state, code) = match network.is_simulated() {
            true => (slave.esm().state(), slave.esm().error().map_or(0, |c| c.code())),
            false => (network.state(), 0),
        };
        slot.al_state = state.code();
        slot.al_status_code = code;
        let (outputs, inputs) = network.slave_images(i);
        let n = outputs.len().min(MAX_PDO_BYTES);
        slot.outputs[..n].copy_from_slice(&outputs[..n]);
        let n = inputs.len().min(MAX_PDO_BYTES);
        slot.inputs[..n].copy_from_slice(&inputs[..n]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::AxisConfig;

    #[test]
    fn a_forced_value_is_written_until_released() {
        let mut net = Network::new(&[AxisConfig::default()]);
        net.start(1_000_000).unwrap();
        let cw = net.output_field(0, 0x6040, 0).unwrap();
        let mut forces = PdoForces::default();
        assert!(forces.force(cw, 0x000F));
        let (_, outputs) = net.images_mut();
        cw.write(outputs, 0);
        forces.apply(outputs);
        assert_eq!(cw.read(outputs), 0x000F);
        assert!(forces.release(cw));
        assert!(!forces.release(cw), "released once");
        cw.write(outputs, 6);
        forces.apply(outputs);
        assert_eq!(cw.read(outputs), 6);
    }

    /// Programs see the second TxPDO too: the snapshot holds both PDOs of a direction, so
    /// `ReadPDO` (HMPL 17.3) finds the touch probe's objects that 0x1A01 maps (CoE 2.4).
    #[test]
    fn the_snapshot_shows_the_second_pdo_to_programs() {
        use api::QueryCall;
        use calls::query::{Value, evaluate};
        let travel = crate::config::TravelConfig { start_position: 1.5, ..Default::default() };
        let mut net = Network::new(&[AxisConfig { counts_per_unit: 10_000.0, travel, ..AxisConfig::default() }]);
        net.start(1_000_000).expect("start-up to Op");
        // 0x60B8 is in the master's second RxPDO: TP1 enabled through process data.
        let function = net.output_field(0, 0x60B8, 0).unwrap();
        function.write(net.images_mut().1, 0x0001);
        net.exchange(1e-3);
        let mut snapshot: Box<Snapshot> = Box::default();
        describe_slaves(&net, &mut snapshot);
        update_slaves(&net, &mut snapshot);
        assert_eq!(snapshot.slaves[0].tx_count, 10, "7 entries of 0x1A00, 3 of the touch probe's 0x1A01");
        let read = |index, sub| match evaluate(
            &QueryCall::ReadPDO { slv_id: 0, obj_index: index, obj_subindex: sub },
            &snapshot,
        ) {
            Ok(answer) => answer.0,
            Err(e) => panic!("ReadPDO 0x{index:04X}: {e:?}"),
        };
        assert_eq!(read(0x6064, 0), Value::Int(15000), "0x1A00: position actual");
        assert_eq!(read(0x60B9, 0), Value::Int(1), "0x1A01: touch probe status, TP1 enabled");
        assert_eq!(read(0x60BA, 0), Value::Int(0), "0x1A01: no positive edge yet");
        assert_eq!(read(0x60BB, 0), Value::Int(0), "0x1A01: no negative edge yet");
        assert_eq!(read(0x60BC, 0), Value::Int(-1), "not mapped");
    }
}
