//! CiA 402 words as they cross the bus: the controlword commands, the statusword state
//! encodings and the touch probe's function and status bits. Both the simulated drives and the motion kernel (the master) speak them.

/// Controlword 0x6040 bits (CoE manual 3.1, table 3-2).
pub mod controlword {
    /// Bit 0, switch on.
    pub const SWITCH_ON: u16 = 1 << 0;
    /// Bit 1, enable voltage: 0 is the Disable voltage command.
    pub const ENABLE_VOLTAGE: u16 = 1 << 1;
    /// Active low: 0 requests a quick stop.
    pub const QUICK_STOP: u16 = 1 << 2;
    /// Bit 3, enable operation: with bits 0-2 set the motor is energised.
    pub const ENABLE_OPERATION: u16 = 1 << 3;
    /// Operation-mode specific: pp new set-point, hm start homing.
    pub const NEW_SET_POINT: u16 = 1 << 4;
    /// pp: change set immediately.
    pub const CHANGE_SET_IMMEDIATELY: u16 = 1 << 5;
    /// pp: the target is relative.
    pub const RELATIVE: u16 = 1 << 6;
    /// Acts on its rising edge.
    pub const FAULT_RESET: u16 = 1 << 7;
    /// Bit 8, halt: pp, pv, tq and hm decelerate to rest; the cyclic modes ignore it.
    pub const HALT: u16 = 1 << 8;

    /// Shutdown, table 3-3's typical value: to Ready to switch on (transitions 2, 6, 8).
    pub const SHUTDOWN: u16 = 0x0006;
    /// Switch on (= disable operation): to Switched on (transitions 3, 5).
    pub const SWITCH_ON_CMD: u16 = 0x0007;
    /// Enable operation: to Operation enabled (transition 4, or 3+4 from Ready to switch
    /// on).
    pub const ENABLE_OPERATION_CMD: u16 = 0x000F;
    /// Disable voltage: to Switch on disabled (transitions 7, 9, 10, 12).
    pub const DISABLE_VOLTAGE: u16 = 0x0000;
    /// Quick stop: Operation enabled to Quick stop active (11), else Switch on disabled
    /// (7, 10).
    pub const QUICK_STOP_CMD: u16 = 0x0002;
}

/// 0x60B8 (touch probe function) and 0x60B9 (status) bits of one probe, CoE tables 3-16,
/// 3-17 and 4-18 for probe 1; probe 2's are `PROBE_2_SHIFT` higher (CiA 402).
pub mod touch_probe {
    /// How many bits higher probe 2's bits sit than probe 1's, in both words.
    pub const PROBE_2_SHIFT: usize = 8;
    /// 0x60B8 bit 0: the probe is switched on.
    pub const ENABLE: u16 = 1 << 0;
    /// 0x60B8 bit 1: trigger on every event (continuous), not on the first only.
    pub const CONTINUOUS: u16 = 1 << 1;
    /// Bits 2-3: 00 the probe's input, 01 the index (the CoE manual's drive: always the index).
    pub const SOURCE: u16 = 0b11 << 2;
    /// Bits 2-3 = 01: the encoder index is the trigger.
    pub const SOURCE_INDEX: u16 = 0b01 << 2;
    /// 0x60B8 bit 4: sample the position on the rising edge (into 0x60BA).
    pub const POSITIVE_EDGE: u16 = 1 << 4;
    /// 0x60B8 bit 5: sample on the falling edge (into 0x60BB); not with bit 4 (table
    /// 4-18:
    /// 11b is reserved).
    pub const NEGATIVE_EDGE: u16 = 1 << 5;
    /// 0x60B9 bit 0: the probe is enabled.
    pub const STATUS_ENABLED: u16 = 1 << 0;
    /// 0x60B9 bit 1: a rising-edge position is stored in 0x60BA.
    pub const STATUS_POSITIVE_STORED: u16 = 1 << 1;
    /// 0x60B9 bit 2: a falling-edge position is stored in 0x60BB.
    pub const STATUS_NEGATIVE_STORED: u16 = 1 << 2;
}

/// Statusword 0x6041 bits (CoE manual 3.1, table 3-4).
pub mod statusword {
    /// Bit 0, ready to switch on.
    pub const READY_TO_SWITCH_ON: u16 = 1 << 0;
    /// Bit 1, switched on.
    pub const SWITCHED_ON: u16 = 1 << 1;
    /// Bit 2, operation enabled: the motor is energised.
    pub const OPERATION_ENABLED: u16 = 1 << 2;
    /// Bit 3, fault: in Fault reaction active or Fault.
    pub const FAULT: u16 = 1 << 3;
    /// Bit 4, voltage enabled: high voltage is applied (CiA 402; not stated by HIWIN).
    pub const VOLTAGE_ENABLED: u16 = 1 << 4;
    /// 1 = not in quick stop.
    pub const QUICK_STOP: u16 = 1 << 5;
    /// Bit 6, switch on disabled.
    pub const SWITCH_ON_DISABLED: u16 = 1 << 6;
    /// Bit 7, warning (the manual defines no source).
    pub const WARNING: u16 = 1 << 7;
    /// Bit 9, remote: the controlword is processed (EtherCAT control).
    pub const REMOTE: u16 = 1 << 9;
    /// Bit 10, target reached: its meaning per mode in tables 3-7, 3-10, 3-12, 3-13.
    pub const TARGET_REACHED: u16 = 1 << 10;
    /// Bit 11, internal limit active: a limit blocks the motion.
    pub const INTERNAL_LIMIT_ACTIVE: u16 = 1 << 11;
    /// Operation-mode specific (pp set-point acknowledge, hm attained, csp target used).
    pub const OMS_12: u16 = 1 << 12;
    /// Operation-mode specific (pp/csp following error, hm homing error).
    pub const OMS_13: u16 = 1 << 13;
}

/// The states of the CiA 402 finite state automaton (CoE manual 3.1, table 3-1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum State {
    /// The drive is initialising.
    NotReadyToSwitchOn,
    /// Main power off; the motor cannot be energised.
    SwitchOnDisabled,
    /// Waiting for main power; the motor cannot be energised yet.
    ReadyToSwitchOn,
    /// Main power on; the controlword can energise the motor.
    SwitchedOn,
    /// The motor is energised and the drive follows its mode of operation.
    OperationEnabled,
    /// The drive stops the motor with the quick stop deceleration 0x6085.
    QuickStopActive,
    /// A fault occurred and the drive carries out its fault reaction.
    FaultReactionActive,
    /// The fault reaction is done and the motor de-energised; a fault reset leaves it.
    Fault,
}

impl State {
    /// The state bits of the statusword (CoE manual 3.1, table 3-5).
    pub fn statusword_bits(self) -> u16 {
        match self {
            State::NotReadyToSwitchOn => 0x0000,
            State::SwitchOnDisabled => 0x0040,
            State::ReadyToSwitchOn => 0x0021,
            State::SwitchedOn => 0x0023,
            State::OperationEnabled => 0x0027,
            State::QuickStopActive => 0x0007,
            State::FaultReactionActive => 0x000F,
            State::Fault => 0x0008,
        }
    }

    /// Decodes a statusword with the masks of table 3-5: 0x004F for the states where bit
    /// 5 is "don't care", 0x006F for the others.
    pub fn from_statusword(sw: u16) -> Option<State> {
        match sw & 0x004F {
            0x0000 => return Some(State::NotReadyToSwitchOn),
            0x0040 => return Some(State::SwitchOnDisabled),
            0x000F => return Some(State::FaultReactionActive),
            0x0008 => return Some(State::Fault),
            _ => {}
        }
        match sw & 0x006F {
            0x0021 => Some(State::ReadyToSwitchOn),
            0x0023 => Some(State::SwitchedOn),
            0x0027 => Some(State::OperationEnabled),
            0x0007 => Some(State::QuickStopActive),
            _ => None,
        }
    }

    /// High voltage is applied (statusword bit 4, CiA 402 practice: not stated by HIWIN).
    pub fn voltage_enabled(self) -> bool {
        matches!(self, State::ReadyToSwitchOn | State::SwitchedOn | State::OperationEnabled | State::QuickStopActive)
    }

    /// The motor is energised and follows its set-points.
    pub fn is_energised(self) -> bool {
        matches!(self, State::OperationEnabled | State::QuickStopActive | State::FaultReactionActive)
    }
}

/// The device-control commands of table 3-3 (fault reset is an edge, see `drive::fsa`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// Transitions 2, 6, 8: to Ready to switch on.
    Shutdown,
    /// Transition 3, or 5 (disable operation) from Operation enabled: to Switched on.
    SwitchOn,
    /// Transition 4 (or 3+4): to Operation enabled.
    EnableOperation,
    /// Transitions 7, 9, 10, 12: to Switch on disabled.
    DisableVoltage,
    /// Transition 11 from Operation enabled, else 7 or 10 to Switch on disabled.
    QuickStop,
}

impl Command {
    /// Decodes the low bits of a controlword in the order that makes the overlapping
    /// masks of table 3-3 unambiguous: disable voltage, quick stop, shutdown, switch on
    /// (= disable operation), enable operation. Bit 7 is ignored here.
    pub fn decode(cw: u16) -> Command {
        use controlword::*;
        if cw & ENABLE_VOLTAGE == 0 {
            Command::DisableVoltage
        } else if cw & QUICK_STOP == 0 {
            Command::QuickStop
        } else if cw & SWITCH_ON == 0 {
            Command::Shutdown
        } else if cw & ENABLE_OPERATION == 0 {
            Command::SwitchOn
        } else {
            Command::EnableOperation
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CoE manual 3.1, table 3-5: every state encodes to bits its own mask decodes.
    #[test]
    fn every_state_decodes_from_its_own_statusword_bits() {
        let states = [
            State::NotReadyToSwitchOn,
            State::SwitchOnDisabled,
            State::ReadyToSwitchOn,
            State::SwitchedOn,
            State::OperationEnabled,
            State::QuickStopActive,
            State::FaultReactionActive,
            State::Fault,
        ];
        for state in states {
            // Bits outside the state masks (voltage, warning, remote, target reached...) do not matter.
            for noise in [0x0000, 0x0010, 0x0080, 0x0200, 0x0400, 0x3E90] {
                let sw = state.statusword_bits() | noise;
                assert_eq!(State::from_statusword(sw), Some(state), "sw = {sw:#06x}");
            }
        }
    }

    /// CoE manual 3.1, table 3-3: typical controlword values.
    #[test]
    fn table_3_3_typical_controlwords() {
        let rows: [(u16, Command); 7] = [
            (0x0006, Command::Shutdown),
            (0x0007, Command::SwitchOn),
            (0x000F, Command::EnableOperation),
            (0x0000, Command::DisableVoltage),
            (0x000D, Command::DisableVoltage),
            (0x0002, Command::QuickStop),
            (0x000B, Command::QuickStop),
        ];
        for (cw, command) in rows {
            assert_eq!(Command::decode(cw), command, "cw = {cw:#06x}");
        }
    }
}
