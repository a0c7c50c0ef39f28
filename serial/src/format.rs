//! DXMC parameter 5-5, the FreePort format word `DCBAUZYX` (nibbles from bit 31 down): YX
//! the start byte, UZ the end byte, A 1 when there is a start byte, B 1 for the end byte
//! UZ or 2 for CR+LF, C reserved, D 1 to clear the receive buffer (back to 0 when done).
//! `FreePort.Serial.Init` returns it as "the value written to P3-09" (D is 0 by then:
//! Init clears the buffer before it answers).

/// The end of a serial frame: what 5-5's nibble B can say.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum End {
    /// B = 0: no end byte.
    None,
    /// B = 1: the end byte UZ.
    Byte(u8),
    /// B = 2: CR LF.
    CrLf,
}

impl End {
    /// The end of a frame that ends with `bytes`: none, one byte or CR LF (5-5 has no
    /// room for other pairs).
    pub fn from_bytes(bytes: &[u8]) -> Option<End> {
        match bytes {
            [] => Some(End::None),
            [b] => Some(End::Byte(*b)),
            b"\r\n" => Some(End::CrLf),
            _ => None,
        }
    }

    /// The end bytes on the line.
    pub(crate) fn bytes(self) -> Vec<u8> {
        match self {
            End::None => Vec::new(),
            End::Byte(b) => vec![b],
            End::CrLf => b"\r\n".to_vec(),
        }
    }
}

/// The word for a start byte and an end (D = 0: a clear is done by the time it is read).
pub fn word(start: Option<u8>, end: End) -> u32 {
    let (a, yx) = start.map_or((0, 0), |b| (1, b));
    let (b, uz) = match end {
        End::None => (0, 0),
        End::Byte(byte) => (1, byte),
        End::CrLf => (2, 0),
    };
    (b << 20) | (a << 16) | (u32::from(uz) << 8) | u32::from(yx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_of_the_manual_s_examples() {
        // Init(1, ":", ";") and Init(1, nil, CR_LF, 0x0C) (DXMC 8.3).
        assert_eq!(word(Some(b':'), End::Byte(b';')), 0x0011_3B3A);
        assert_eq!(word(None, End::CrLf), 0x0020_0000);
        assert_eq!(word(None, End::None), 0);
        assert_eq!(word(Some(0xFF), End::Byte(0xFF)), 0x0011_FFFF);
    }
}
