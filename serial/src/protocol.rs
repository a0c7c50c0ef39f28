//! DXMC parameter 5-1, the serial protocol: one code per character frame and protocol
//! (DXMC 8.2 and the parameter table of 5-1; `FreePort.Serial.Init` takes the FreePort rows).

/// How a frame's protocol is carried.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Modbus ASCII (DXMC 8.2): hex characters, LRC.
    ModbusAscii,
    /// Modbus RTU (DXMC 8.2): binary, CRC-16.
    ModbusRtu,
    /// FreePort (DXMC 8.3): the program's own frames, delimited by parameter 5-5.
    FreePort,
}

/// A character frame's parity bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parity {
    /// No parity bit (N).
    None,
    /// Even parity (E).
    Even,
    /// Odd parity (O).
    Odd,
}

/// A character frame: data bits, parity, stop bits (`8,N,1`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CharFrame {
    /// Data bits per character: 7 or 8.
    pub data_bits: u8,
    /// The parity bit, if any.
    pub parity: Parity,
    /// Stop bits per character: 1 or 2.
    pub stop_bits: u8,
}

impl std::fmt::Display for CharFrame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parity = match self.parity {
            Parity::None => 'N',
            Parity::Even => 'E',
            Parity::Odd => 'O',
        };
        write!(f, "{},{parity},{}", self.data_bits, self.stop_bits)
    }
}

/// One row of parameter 5-1: its code, character frame and protocol.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Protocol {
    /// The value of parameter 5-1.
    pub code: u8,
    /// The character frame on the line.
    pub frame: CharFrame,
    /// Modbus ASCII, Modbus RTU or FreePort.
    pub kind: Kind,
}

const fn row(code: u8, data_bits: u8, parity: Parity, stop_bits: u8, kind: Kind) -> Protocol {
    Protocol { code, frame: CharFrame { data_bits, parity, stop_bits }, kind }
}

use Kind::{FreePort as Fp, ModbusAscii as Ascii, ModbusRtu as Rtu};
use Parity::{Even as E, None as N, Odd as O};

/// Parameter 5-1, codes 0x00..0x1D in order. The table prints 0x14 as "7,E,2 (Freeport)";
/// `FreePort.Serial.Init`'s list has it as 7,O,2, which completes the pattern.
pub const TABLE: [Protocol; 30] = [
    row(0x00, 7, N, 2, Ascii),
    row(0x01, 7, E, 1, Ascii),
    row(0x02, 7, O, 1, Ascii),
    row(0x03, 8, N, 2, Ascii),
    row(0x04, 8, E, 1, Ascii),
    row(0x05, 8, O, 1, Ascii),
    row(0x06, 8, N, 2, Rtu),
    row(0x07, 8, E, 1, Rtu),
    row(0x08, 8, O, 1, Rtu),
    row(0x09, 7, N, 2, Fp),
    row(0x0A, 7, E, 1, Fp),
    row(0x0B, 7, O, 1, Fp),
    row(0x0C, 8, N, 2, Fp),
    row(0x0D, 8, E, 1, Fp),
    row(0x0E, 8, O, 1, Fp),
    row(0x0F, 7, N, 1, Ascii),
    row(0x10, 7, N, 1, Fp),
    row(0x11, 7, E, 2, Ascii),
    row(0x12, 7, E, 2, Fp),
    row(0x13, 7, O, 2, Ascii),
    row(0x14, 7, O, 2, Fp),
    row(0x15, 8, N, 1, Ascii),
    row(0x16, 8, N, 1, Rtu),
    row(0x17, 8, N, 1, Fp),
    row(0x18, 8, E, 2, Ascii),
    row(0x19, 8, E, 2, Rtu),
    row(0x1A, 8, E, 2, Fp),
    row(0x1B, 8, O, 2, Ascii),
    row(0x1C, 8, O, 2, Rtu),
    row(0x1D, 8, O, 2, Fp),
];

impl Protocol {
    /// The row of code `code` of parameter 5-1, `None` beyond 0x1D.
    pub fn from_code(code: i64) -> Option<Protocol> {
        usize::try_from(code).ok().and_then(|i| TABLE.get(i)).copied()
    }

    /// The FreePort code with the same character frame (`FreePort.Serial.Init` without a
    /// protocol keeps the line's frame). Every frame of the table has one.
    pub fn freeport(self) -> Protocol {
        TABLE.into_iter().find(|p| p.kind == Kind::FreePort && p.frame == self.frame).unwrap_or(self)
    }
}

/// DXMC parameter 5-4: 0 4800, 1 9600, 2 19200, 3 38400 (the default), 4 57600, 5 115200.
pub const BAUDS: [u32; 6] = [4800, 9600, 19200, 38400, 57600, 115_200];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameter_5_1_table() {
        // Code, frame as the manual prints it, kind: DXMC 8.3 (FreePort.Serial.Init) and 5-1.
        let rows: [(u8, &str, Kind); 30] = [
            (0x00, "7,N,2", Ascii),
            (0x01, "7,E,1", Ascii),
            (0x02, "7,O,1", Ascii),
            (0x03, "8,N,2", Ascii),
            (0x04, "8,E,1", Ascii),
            (0x05, "8,O,1", Ascii),
            (0x06, "8,N,2", Rtu),
            (0x07, "8,E,1", Rtu),
            (0x08, "8,O,1", Rtu),
            (0x09, "7,N,2", Fp),
            (0x0A, "7,E,1", Fp),
            (0x0B, "7,O,1", Fp),
            (0x0C, "8,N,2", Fp),
            (0x0D, "8,E,1", Fp),
            (0x0E, "8,O,1", Fp),
            (0x0F, "7,N,1", Ascii),
            (0x10, "7,N,1", Fp),
            (0x11, "7,E,2", Ascii),
            (0x12, "7,E,2", Fp),
            (0x13, "7,O,2", Ascii),
            (0x14, "7,O,2", Fp),
            (0x15, "8,N,1", Ascii),
            (0x16, "8,N,1", Rtu),
            (0x17, "8,N,1", Fp),
            (0x18, "8,E,2", Ascii),
            (0x19, "8,E,2", Rtu),
            (0x1A, "8,E,2", Fp),
            (0x1B, "8,O,2", Ascii),
            (0x1C, "8,O,2", Rtu),
            (0x1D, "8,O,2", Fp),
        ];
        for (code, frame, kind) in rows {
            let p = Protocol::from_code(code.into()).unwrap();
            assert_eq!((p.code, p.frame.to_string().as_str(), p.kind), (code, frame, kind));
        }
        assert_eq!(Protocol::from_code(0x1E), None);
        assert_eq!(Protocol::from_code(-1), None);
    }

    #[test]
    fn every_frame_has_a_freeport_code() {
        for p in TABLE {
            let fp = p.freeport();
            assert_eq!((fp.kind, fp.frame), (Kind::FreePort, p.frame), "{:#04x}", p.code);
        }
        assert_eq!(Protocol::from_code(0x16).unwrap().freeport().code, 0x17);
    }
}
