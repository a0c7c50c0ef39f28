//! `[[slaves]]`: the devices on the bus that drive no axis, the terminals.

use serde::Deserialize;

use crate::error::{ConfigError, invalid};

/// `[[slaves]]`: a device on the bus beside the axes' drives.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlaveConfig {
    /// What kind of terminal it is.
    pub device: SlaveDevice,
    /// Input channels: 0..=32 of a `digital_io` terminal, 0..=4 of an `analog_io` one.
    #[serde(default)]
    pub inputs: u8,
    /// Output channels, as many as `inputs` may be.
    #[serde(default)]
    pub outputs: u8,
    /// An `analog_io` terminal's output n wired to its input n (docs/decisions.md,
    /// "Slave analog I/O"); a `digital_io` terminal has no such wiring.
    #[serde(default)]
    pub loopback: bool,
}

/// Channels a `digital_io` terminal may have: one 32-bit process-data word each way.
pub const MAX_TERMINAL_CHANNELS: u8 = 32;

/// The kinds of device a `[[slaves]]` entry may name; any other is refused with the name
/// it gave (docs/decisions.md, "`[[slaves]]`").
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SlaveDevice {
    /// A digital I/O terminal (HMPL 9.3, 9.5): `inputs` and `outputs` channels.
    DigitalIo,
    /// An analog I/O terminal (HMPL ch. 10): `inputs` and `outputs` 16-bit channels.
    AnalogIo,
}

impl SlaveDevice {
    /// The channels the kind may have each way.
    pub fn max_channels(self) -> u8 {
        match self {
            SlaveDevice::DigitalIo => MAX_TERMINAL_CHANNELS,
            SlaveDevice::AnalogIo => schema::MAX_ANALOG_CHANNELS as u8,
        }
    }
}

/// The `[[slaves]]` entries: each kind's channels, its wiring, and room in the snapshot
/// for the analog terminals.
pub(crate) fn validate_slaves(slaves: &[SlaveConfig]) -> Result<(), ConfigError> {
    for (i, slave) in slaves.iter().enumerate() {
        let max = slave.device.max_channels();
        for (key, count) in [("inputs", slave.inputs), ("outputs", slave.outputs)] {
            if count > max {
                let kind = format!("a {:?} terminal has 0..{max} channels", slave.device);
                return Err(invalid(format!("slaves[{i}].{key}"), kind));
            }
        }
        let analog = slaves[..=i].iter().filter(|s| s.device == SlaveDevice::AnalogIo).count();
        if analog > schema::MAX_ANALOG_TERMINALS {
            let room = format!("at most {} analog_io terminals", schema::MAX_ANALOG_TERMINALS);
            return Err(invalid(format!("slaves[{i}]"), room));
        }
        if slave.loopback && slave.device != SlaveDevice::AnalogIo {
            return Err(invalid(format!("slaves[{i}].loopback"), "only an analog_io terminal has a loopback"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `[[slaves]]` entries of `text`, a TOML array of tables.
    fn parse(text: &str) -> Vec<SlaveConfig> {
        #[derive(Deserialize)]
        struct Slaves {
            slaves: Vec<SlaveConfig>,
        }
        toml::from_str::<Slaves>(text).unwrap().slaves
    }

    fn key(slaves: &[SlaveConfig]) -> Option<String> {
        match validate_slaves(slaves) {
            Err(ConfigError::Invalid { key, .. }) => Some(key),
            _ => None,
        }
    }

    /// A `digital_io` terminal: its channel counts, at most 32 each way.
    #[test]
    fn digital_io_terminals() {
        let slaves = parse("[[slaves]]\ndevice = \"digital_io\"\ninputs = 16\noutputs = 8\n");
        let slave = &slaves[0];
        assert_eq!((slave.device, slave.inputs, slave.outputs), (SlaveDevice::DigitalIo, 16, 8));
        assert!(validate_slaves(&slaves).is_ok());
        let slaves = parse("[[slaves]]\ndevice = \"digital_io\"\noutputs = 33\n");
        assert_eq!(key(&slaves).as_deref(), Some("slaves[0].outputs"), "33 outputs");
    }

    /// An `analog_io` terminal: at most 4 channels each way; only it has a loopback.
    #[test]
    fn analog_io_terminals() {
        let slaves = parse("[[slaves]]\ndevice = \"analog_io\"\ninputs = 2\noutputs = 4\nloopback = true\n");
        let s = &slaves[0];
        assert_eq!((s.device, s.inputs, s.outputs, s.loopback), (SlaveDevice::AnalogIo, 2, 4, true));
        assert!(validate_slaves(&slaves).is_ok());
        let slaves = parse("[[slaves]]\ndevice = \"analog_io\"\ninputs = 5\n");
        assert_eq!(key(&slaves).as_deref(), Some("slaves[0].inputs"));
        let slaves = parse("[[slaves]]\ndevice = \"digital_io\"\nloopback = true\n");
        assert_eq!(key(&slaves).as_deref(), Some("slaves[0].loopback"));
        let nine = parse(&"[[slaves]]\ndevice = \"analog_io\"\n".repeat(9));
        assert_eq!(key(&nine).as_deref(), Some("slaves[8]"), "9 terminals");
    }
}
