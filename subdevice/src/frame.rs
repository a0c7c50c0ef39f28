//! The EtherCAT frame on Ethernet: the Ethernet header with EtherType 0x88A4, the 2-byte
//! EtherCAT header (ETG.1000.4 5.3: 11 bits of length, 4 bits of type) and the datagrams
//! (DLPDUs) that follow one another while their `M` bit says so (ETG.1000.4 5.4.1.2,
//! table 14 and the other commands' tables: command, index, address, length with the `C`
//! and `M` bits, IRQ, data, working counter).
//!
//! Nothing here panics on any input: a frame is checked whole before any datagram is
//! processed, as a frame an ESC finds broken is forwarded with a spoilt checksum and the
//! master discards it.

use std::ops::Range;

/// EtherType of EtherCAT (ETG.1000.4 5.3).
pub const ETHERTYPE: u16 = 0x88A4;
/// Destination, source, EtherType.
pub const ETHERNET_HEADER_LEN: usize = 14;
/// The EtherCAT header: length and type.
pub const ECAT_HEADER_LEN: usize = 2;
/// Command, index, address, length/C/M, IRQ (ETG.1000.4 table 14).
pub const DATAGRAM_HEADER_LEN: usize = 10;
/// The working counter after a datagram's data.
pub const WKC_LEN: usize = 2;
/// EtherCAT header type 1: the frame carries DLPDUs (ETG.1000.4 5.3).
pub const TYPE_DLPDU: u8 = 1;

/// 11 bits of length, in the EtherCAT header and in each datagram's length field.
const LENGTH_MASK: u16 = 0x07FF;
/// The datagram length field's circulating (`C`, bit 14) and more-follows (`M`, bit 15) bits.
const CIRCULATING: u16 = 1 << 14;
const MORE: u16 = 1 << 15;
/// Bit 1 of the first source-address octet: the U/L ("locally administered") bit an ESC's
/// port 0 sets in the frames it sends back to the master.
const LOCALLY_ADMINISTERED: u8 = 0x02;
/// Where the source address starts in the Ethernet header.
const SOURCE_ADDRESS: usize = 6;

/// Why a frame is not processed. The segment drops such a frame: nothing goes back.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// Shorter than the Ethernet and EtherCAT headers.
    #[error("{0} bytes: too short for the Ethernet and EtherCAT headers")]
    TooShort(usize),
    /// Another protocol on the wire (a VLAN tag included).
    #[error("EtherType 0x{0:04X} is not EtherCAT's 0x88A4")]
    NotEtherCat(u16),
    /// An EtherCAT header type other than DLPDU (network variables, mailbox gateway).
    #[error("EtherCAT frame type {0}: only DLPDUs (type 1) are processed")]
    UnsupportedType(u8),
    /// The EtherCAT header claims more bytes than the frame has.
    #[error("the EtherCAT header claims {claimed} bytes, the frame has {available}")]
    LengthPastFrame {
        /// Bytes the header claims.
        claimed: usize,
        /// Bytes after the EtherCAT header.
        available: usize,
    },
    /// A datagram's length (or a missing end of the `M` chain) runs past the header's length.
    #[error("datagram {datagram} needs {needed} bytes, {available} remain in the frame")]
    DatagramPastFrame {
        /// The datagram's position in the frame, from 0.
        datagram: usize,
        /// Its header, data and working counter.
        needed: usize,
        /// What the EtherCAT header's length leaves for it.
        available: usize,
    },
    /// A header length too short for even one datagram.
    #[error("the frame holds no datagram")]
    NoDatagram,
}

/// The EtherCAT header (ETG.1000.4 5.3): the length of the datagrams and the type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EcatHeader {
    /// Bytes of datagrams that follow (11 bits).
    pub length: u16,
    /// Protocol type (4 bits); 1 is DLPDU.
    pub kind: u8,
}

impl EcatHeader {
    /// Reads the little-endian header word.
    pub fn parse(bytes: [u8; 2]) -> Self {
        let word = u16::from_le_bytes(bytes);
        EcatHeader { length: word & LENGTH_MASK, kind: (word >> 12) as u8 }
    }

    /// The header word as it goes on the wire.
    pub fn to_bytes(self) -> [u8; 2] {
        ((self.length & LENGTH_MASK) | (u16::from(self.kind) << 12)).to_le_bytes()
    }
}

/// One datagram's header (ETG.1000.4 5.4.1.2, table 14; the same layout for every command).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DatagramHeader {
    /// The command code; one no table lists passes the ESCs unprocessed.
    pub command: u8,
    /// The master's index, returned as sent.
    pub index: u8,
    /// ADP in the low 16 bits and ADO in the high 16, or one 32-bit logical address.
    pub address: u32,
    /// Bytes of data (11 bits).
    pub length: u16,
    /// `C`: the frame has circulated.
    pub circulating: bool,
    /// `M`: another datagram follows.
    pub more: bool,
    /// The event request bits the ESCs OR in.
    pub irq: u16,
}

impl DatagramHeader {
    /// Reads the 10 header bytes.
    pub fn parse(bytes: &[u8; DATAGRAM_HEADER_LEN]) -> Self {
        let word = |i: usize| u16::from_le_bytes([bytes[i], bytes[i + 1]]);
        let flags = word(6);
        DatagramHeader {
            command: bytes[0],
            index: bytes[1],
            address: u32::from_le_bytes([bytes[2], bytes[3], bytes[4], bytes[5]]),
            length: flags & LENGTH_MASK,
            circulating: flags & CIRCULATING != 0,
            more: flags & MORE != 0,
            irq: word(8),
        }
    }

    /// Writes the header back as it leaves an ESC.
    pub fn write(&self, bytes: &mut [u8; DATAGRAM_HEADER_LEN]) {
        let flags = (self.length & LENGTH_MASK)
            | if self.circulating { CIRCULATING } else { 0 }
            | if self.more { MORE } else { 0 };
        bytes[0] = self.command;
        bytes[1] = self.index;
        bytes[2..6].copy_from_slice(&self.address.to_le_bytes());
        bytes[6..8].copy_from_slice(&flags.to_le_bytes());
        bytes[8..10].copy_from_slice(&self.irq.to_le_bytes());
    }

    /// The position or configured station address (ADP).
    pub fn adp(&self) -> u16 {
        self.address as u16
    }

    /// The register or memory offset (ADO).
    pub fn ado(&self) -> u16 {
        (self.address >> 16) as u16
    }

    /// Replaces ADP, as an ESC increments it for position and broadcast commands.
    pub fn set_adp(&mut self, adp: u16) {
        self.address = (self.address & 0xFFFF_0000) | u32::from(adp);
    }
}

/// Where one datagram lies in the frame's bytes (Ethernet header included).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DatagramPlace {
    /// Offset of its 10 header bytes.
    pub header: usize,
    /// Its data.
    pub data: Range<usize>,
    /// Offset of its working counter.
    pub wkc: usize,
}

/// The datagrams of an Ethernet frame, each checked to lie within the EtherCAT header's
/// length, which must lie within the frame (an Ethernet pad after it is allowed).
/// `places` is cleared and filled, so that a server reuses one vector.
pub fn layout(frame: &[u8], places: &mut Vec<DatagramPlace>) -> Result<(), FrameError> {
    places.clear();
    let start = ETHERNET_HEADER_LEN + ECAT_HEADER_LEN;
    if frame.len() < start {
        return Err(FrameError::TooShort(frame.len()));
    }
    let ethertype = u16::from_be_bytes([frame[12], frame[13]]);
    if ethertype != ETHERTYPE {
        return Err(FrameError::NotEtherCat(ethertype));
    }
    let header = EcatHeader::parse([frame[ETHERNET_HEADER_LEN], frame[ETHERNET_HEADER_LEN + 1]]);
    if header.kind != TYPE_DLPDU {
        return Err(FrameError::UnsupportedType(header.kind));
    }
    let end = start + usize::from(header.length);
    if end > frame.len() {
        return Err(FrameError::LengthPastFrame { claimed: header.length.into(), available: frame.len() - start });
    }
    if usize::from(header.length) < DATAGRAM_HEADER_LEN + WKC_LEN {
        return Err(FrameError::NoDatagram);
    }
    let mut at = start;
    loop {
        let available = end - at;
        let datagram = places.len();
        let past = |needed| FrameError::DatagramPastFrame { datagram, needed, available };
        if available < DATAGRAM_HEADER_LEN {
            return Err(past(DATAGRAM_HEADER_LEN + WKC_LEN));
        }
        let mut bytes = [0u8; DATAGRAM_HEADER_LEN];
        bytes.copy_from_slice(&frame[at..at + DATAGRAM_HEADER_LEN]);
        let head = DatagramHeader::parse(&bytes);
        let needed = DATAGRAM_HEADER_LEN + usize::from(head.length) + WKC_LEN;
        if needed > available {
            return Err(past(needed));
        }
        let data = at + DATAGRAM_HEADER_LEN..at + DATAGRAM_HEADER_LEN + usize::from(head.length);
        places.push(DatagramPlace { header: at, wkc: data.end, data });
        at += needed;
        if !head.more {
            return Ok(());
        }
    }
}

/// Marks a frame as sent back by an ESC's port 0: the source address becomes a locally
/// administered one (the first octet's U/L bit set), which is how a master tells its own
/// frame from the one the segment returns.
pub fn mark_returned(frame: &mut [u8]) {
    if let Some(octet) = frame.get_mut(SOURCE_ADDRESS) {
        *octet |= LOCALLY_ADMINISTERED;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An Ethernet header from SOEM's source address (01:01:01:01:01:01) to broadcast.
    const ETHERNET: [u8; 14] = [0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 1, 1, 1, 1, 1, 1, 0x88, 0xA4];

    fn frame(ecat: &[u8]) -> Vec<u8> {
        [&ETHERNET[..], ecat].concat()
    }

    /// A BRD of register 0x0000, 2 bytes (what SOEM sends to count the slaves): header
    /// 0x100E (type 1, 14 bytes), then command 7, index 0x2A, ADP 0, ADO 0, length 2.
    const BRD: [u8; 16] = [0x0E, 0x10, 0x07, 0x2A, 0, 0, 0, 0, 0x02, 0x00, 0, 0, 0, 0, 0, 0];

    #[test]
    fn the_headers_read_and_write_as_etg_1000_4_lays_them_out() {
        assert_eq!(EcatHeader::parse([0x0E, 0x10]), EcatHeader { length: 14, kind: 1 });
        assert_eq!(EcatHeader { length: 14, kind: 1 }.to_bytes(), [0x0E, 0x10]);
        let bytes = [0x0C, 0x05, 0xE9, 0x03, 0x30, 0x01, 0x02, 0xC0, 0x34, 0x12];
        let head = DatagramHeader::parse(&bytes);
        assert_eq!(
            head,
            DatagramHeader {
                command: 0x0C,
                index: 5,
                address: 0x0130_03E9,
                length: 2,
                circulating: true,
                more: true,
                irq: 0x1234
            }
        );
        assert_eq!((head.adp(), head.ado()), (0x03E9, 0x0130));
        let mut back = [0u8; 10];
        head.write(&mut back);
        assert_eq!(back, bytes);
    }

    #[test]
    fn datagrams_follow_one_another_while_m_is_set() {
        let mut two = BRD.to_vec();
        two[0] = 28;
        two[8] = 0x02;
        two[9] = 0x80;
        two.extend_from_slice(&[0x04, 0x2B, 0xE9, 0x03, 0x30, 0x01, 0x02, 0x00, 0, 0, 0, 0, 0, 0]);
        let mut places = Vec::new();
        layout(&frame(&two), &mut places).unwrap();
        assert_eq!(
            places,
            [DatagramPlace { header: 16, data: 26..28, wkc: 28 }, DatagramPlace { header: 30, data: 40..42, wkc: 42 }]
        );
    }

    /// A frame padded to Ethernet's 60 bytes is fine: the header's length decides.
    #[test]
    fn an_ethernet_pad_after_the_datagrams_is_allowed() {
        let mut padded = frame(&BRD);
        padded.resize(60, 0);
        let mut places = Vec::new();
        assert_eq!(layout(&padded, &mut places), Ok(()));
        assert_eq!(places.len(), 1);
    }

    /// Each broken frame has its typed error, one row per case.
    #[test]
    fn broken_frames_are_refused_with_their_reason() {
        let mut long_datagram = BRD;
        long_datagram[8] = 0x40;
        let mut long_header = BRD;
        long_header[0] = 0x40;
        let mut not_dlpdu = BRD;
        not_dlpdu[1] = 0x50;
        let mut unended = BRD;
        unended[9] = 0x80;
        let mut vlan = frame(&BRD);
        vlan[12..14].copy_from_slice(&[0x81, 0x00]);
        let rows: [(Vec<u8>, FrameError); 7] = [
            (ETHERNET[..10].to_vec(), FrameError::TooShort(10)),
            (vlan, FrameError::NotEtherCat(0x8100)),
            (frame(&not_dlpdu), FrameError::UnsupportedType(5)),
            (frame(&long_header), FrameError::LengthPastFrame { claimed: 64, available: 14 }),
            (frame(&long_datagram), FrameError::DatagramPastFrame { datagram: 0, needed: 76, available: 14 }),
            (frame(&unended), FrameError::DatagramPastFrame { datagram: 1, needed: 12, available: 0 }),
            (frame(&[0x02, 0x10, 0, 0]), FrameError::NoDatagram),
        ];
        let mut places = Vec::new();
        for (bytes, error) in rows {
            assert_eq!(layout(&bytes, &mut places), Err(error), "{error}");
        }
    }

    #[test]
    fn the_returned_frame_has_a_locally_administered_source() {
        let mut bytes = frame(&BRD);
        mark_returned(&mut bytes);
        assert_eq!(&bytes[6..12], &[3, 1, 1, 1, 1, 1]);
        mark_returned(&mut []);
    }
}
