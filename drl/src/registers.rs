//! The Modbus address map, DXMC manual appendix A.1 and A.3: which word an address is,
//! whether it can be written, and the limit of words per request (8.2).

/// DXMC 8.2: at most 10 words per request (FC 03 and FC 16).
pub const MAX_WORDS: u16 = 10;

/// A register luamotion answers. Every other address is "illegal data address".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Register {
    /// DV 0x0000..0x2FFF or DH 0x8000..0xAFFF (A.1), by Modbus address.
    User(u16),
    /// 0x3000..0x5BDE, in the SDV range A.1 reserves: the FUN147 register image
    /// (docs/fun147.md, `calls::plc`), by Modbus address.
    Plc(u16),
    /// 0x6A80: current controller state (read only).
    ControllerState,
    /// 0x6A81: target controller state, 2, 4 or 5.
    TargetState,
    /// 0x6B00: the current DRL id (read only).
    DrlId,
    /// 0x6B01: the execution state (read only).
    ExecState,
    /// 0x6B02: the current line of `main.lua` (read only).
    Line,
    /// 0x6B03: run speed, %. The manual gives no way to write it; here it is written here.
    RunSpeed,
    /// 0x6B04: the DRL id selected for the next command, 0..9999.
    IdSelect,
    /// 0x6B05: the control command.
    Control,
    /// 0x6B06: the status of the last command (read only).
    Status,
    /// 0x6B07..0x6B0E (reserved in the manual): the breakpoint lines Set BP takes;
    /// Add BP and Delete BP take the first.
    Breakpoint(usize),
    /// 0x6B10: PLC control, 0 ColdStart, 1 WarmStart, 2 HotStart, 3 Stop.
    PlcControl,
    /// 0x6B11: PLC status (read only).
    PlcStatus,
}

/// The breakpoint registers: as many as Set BP may set before a run (A.3 note: 8).
pub const BREAKPOINT_REGISTERS: usize = 8;
const BREAKPOINT_BASE: u16 = 0x6B07;

impl Register {
    /// The register at a Modbus address (DXMC A.1 to A.3), `None` for one the map lacks.
    pub fn at(address: u16) -> Option<Self> {
        Some(match address {
            0x0000..=0x2FFF | 0x8000..=0xAFFF => Register::User(address),
            a if calls::plc::PlcWord::at(a).is_some() => Register::Plc(a),
            0x6A80 => Register::ControllerState,
            0x6A81 => Register::TargetState,
            0x6B00 => Register::DrlId,
            0x6B01 => Register::ExecState,
            0x6B02 => Register::Line,
            0x6B03 => Register::RunSpeed,
            0x6B04 => Register::IdSelect,
            0x6B05 => Register::Control,
            0x6B06 => Register::Status,
            a @ 0x6B07..=0x6B0E => Register::Breakpoint((a - BREAKPOINT_BASE) as usize),
            0x6B10 => Register::PlcControl,
            0x6B11 => Register::PlcStatus,
            _ => return None,
        })
    }

    /// Whether a client may write it (the state and status displays are read-only).
    pub fn writable(self) -> bool {
        !matches!(
            self,
            Register::ControllerState
                | Register::DrlId
                | Register::ExecState
                | Register::Line
                | Register::Status
                | Register::PlcStatus
        )
    }
}

/// Why a request is refused, as a Modbus exception (the server maps each to its code).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Refusal {
    /// Exception 01: only FC 03, 06 and 16.
    #[error("illegal function")]
    IllegalFunction,
    /// Exception 02: an address outside the map, or a read-only register written.
    #[error("illegal data address")]
    IllegalAddress,
    /// Exception 03: more than 10 words, or a value a register does not take.
    #[error("illegal data value")]
    IllegalValue,
}

/// The registers of `count` words from `address`, each checked; writes need writable ones.
pub fn span(address: u16, count: u16, write: bool) -> Result<Vec<Register>, Refusal> {
    if count == 0 || count > MAX_WORDS {
        return Err(Refusal::IllegalValue);
    }
    (0..count)
        .map(|i| {
            let register = address.checked_add(i).and_then(Register::at).ok_or(Refusal::IllegalAddress)?;
            if write && !register.writable() {
                return Err(Refusal::IllegalAddress);
            }
            Ok(register)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// DXMC A.1/A.3, one row per address.
    #[test]
    fn the_address_map() {
        let rows = [
            (0x0000, Some(Register::User(0x0000))),
            (0x0050, Some(Register::User(0x0050))), // %MW3.160
            (0x2FFF, Some(Register::User(0x2FFF))),
            (0x3000, Some(Register::Plc(0x3000))), // SDV: R0 of the FUN147 image
            (0x5AA0, None),                        // D4000 does not exist
            (0x5BDF, None),                        // past S999
            (0x6A80, Some(Register::ControllerState)),
            (0x6A81, Some(Register::TargetState)),
            (0x6A82, None),
            (0x6B00, Some(Register::DrlId)),     // 27392
            (0x6B01, Some(Register::ExecState)), // 27393
            (0x6B02, Some(Register::Line)),      // 27394
            (0x6B03, Some(Register::RunSpeed)),  // 27395
            (0x6B04, Some(Register::IdSelect)),  // 27396
            (0x6B05, Some(Register::Control)),   // 27397
            (0x6B06, Some(Register::Status)),    // 27398
            (0x6B07, Some(Register::Breakpoint(0))),
            (0x6B0E, Some(Register::Breakpoint(7))),
            (0x6B0F, None),
            (0x6B10, Some(Register::PlcControl)),
            (0x6B11, Some(Register::PlcStatus)),
            (0x7FFF, None),
            (0x8000, Some(Register::User(0x8000))), // DH
            (0xAFFF, Some(Register::User(0xAFFF))),
            (0xB000, None), // SDH, "do not use"
            (0xFFFF, None),
        ];
        for (address, register) in rows {
            assert_eq!(Register::at(address), register, "0x{address:04X}");
        }
        assert_eq!(0x6B00, 27392, "Modbus decimal address of 0x6B00");
    }

    /// DXMC 8.2: at most 10 words per request.
    #[test]
    fn ten_words_at_most() {
        assert_eq!(span(0x0000, 10, false).map(|r| r.len()), Ok(10));
        assert_eq!(span(0x0000, 11, false), Err(Refusal::IllegalValue));
        assert_eq!(span(0x0000, 0, false), Err(Refusal::IllegalValue));
    }

    #[test]
    fn reads_and_writes_stay_on_known_registers() {
        assert_eq!(span(0x6B00, 7, false).map(|r| r.len()), Ok(7));
        assert_eq!(span(0x6B0A, 10, false), Err(Refusal::IllegalAddress), "runs into 0x6B0F");
        assert_eq!(span(0x6B06, 1, true), Err(Refusal::IllegalAddress), "status is read only");
        assert_eq!(span(0x6B04, 2, true).map(|r| r.len()), Ok(2));
        assert_eq!(span(0xFFFF, 2, false), Err(Refusal::IllegalAddress));
    }
}
