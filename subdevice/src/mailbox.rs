//! The mailbox of one ESC's application: the mailbox header (ETG.1000.4 5.5, table 29 of
//! ETG.1000.6), CoE SDO download (expedited, normal and segmented) and upload, with CiA 301
//! abort codes (ETG.1000.6 5.6.2, tables 30-41), and the mailbox error reply for a message
//! it cannot take (ETG.1000.6 5.5, table 30). Every SDO is answered by the slave's own
//! `sdo_read`/`sdo_write`: the object rules, the PDO mapping rules in PreOp and the CoE
//! manual's abort codes are the dictionary's, here only carried.

use std::collections::VecDeque;

use devices::ecat::SdoAbort;
use devices::ecat::SdoError;
use devices::ecat::slave::Slave;
use num_enum::TryFromPrimitive;

/// Length, address, channel and priority, type and counter.
pub const MAILBOX_HEADER_LEN: usize = 6;
/// CoE header, command, index, sub-index, 4 data bytes: the shortest SDO message.
pub const SDO_LEN: usize = 10;
/// Replies a mailbox keeps while the master has not fetched the previous one.
const OUTBOX_LEN: usize = 8;
/// The longest download taken: no object of a CoE dictionary here is longer, and the
/// buffer of an open transfer stays bounded.
const MAX_DOWNLOAD: usize = 1024;

/// Mailbox types (ETG.1000.4 5.5). An unknown one is an error (`TryFromPrimitive`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive)]
#[repr(u8)]
pub enum MailboxType {
    /// A mailbox error reply.
    Error = 0x00,
    /// ADS over EtherCAT.
    Aoe = 0x01,
    /// Ethernet over EtherCAT.
    Eoe = 0x02,
    /// CANopen over EtherCAT.
    Coe = 0x03,
    /// File access over EtherCAT.
    Foe = 0x04,
    /// Servo profile over EtherCAT.
    Soe = 0x05,
    /// Vendor specific.
    Voe = 0x0F,
}

/// Detail codes of the mailbox error reply (ETG.1000.6 table 30).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum MailboxError {
    /// A protocol this ESC does not serve.
    UnsupportedProtocol = 0x02,
    /// A service of the protocol it does not serve.
    ServiceNotSupported = 0x04,
    /// The message is shorter than its protocol needs.
    SizeTooShort = 0x06,
    /// The header's length does not fit the mailbox.
    InvalidSize = 0x08,
}

/// CoE services (ETG.1000.6 table 29, upper 4 bits of the CoE header).
const COE_SDO_REQUEST: u16 = 2;
const COE_SDO_RESPONSE: u16 = 3;

/// SDO command specifiers (ETG.1000.6 5.6.2; bits 5-7 of the command byte).
const CCS_DOWNLOAD_SEGMENT: u8 = 0x00;
const CCS_INITIATE_DOWNLOAD: u8 = 0x20;
const CCS_INITIATE_UPLOAD: u8 = 0x40;
const CCS_UPLOAD_SEGMENT: u8 = 0x60;
const CCS_ABORT: u8 = 0x80;
const SIZE_INDICATED: u8 = 0x01;
const EXPEDITED: u8 = 0x02;
const COMPLETE_ACCESS: u8 = 0x10;
const TOGGLE: u8 = 0x10;
const LAST_SEGMENT: u8 = 0x01;

/// A mailbox header (ETG.1000.4 5.5).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MailboxHeader {
    /// Bytes after the header.
    pub length: u16,
    /// Station address of the source (master: 0).
    pub address: u16,
    /// Channel (bits 0-5) and priority (6-7).
    pub channel: u8,
    /// Type (bits 0-3) and counter (4-6).
    pub kind: u8,
}

impl MailboxHeader {
    /// Reads the first 6 bytes.
    pub fn parse(bytes: &[u8; MAILBOX_HEADER_LEN]) -> Self {
        MailboxHeader {
            length: u16::from_le_bytes([bytes[0], bytes[1]]),
            address: u16::from_le_bytes([bytes[2], bytes[3]]),
            channel: bytes[4],
            kind: bytes[5],
        }
    }

    /// The 6 bytes.
    pub fn to_bytes(self) -> [u8; MAILBOX_HEADER_LEN] {
        let [l0, l1] = self.length.to_le_bytes();
        let [a0, a1] = self.address.to_le_bytes();
        [l0, l1, a0, a1, self.channel, self.kind]
    }

    /// The mailbox type code (bits 0-3).
    pub fn type_code(self) -> u8 {
        self.kind & 0x0F
    }
}

/// An SDO transfer under way.
#[derive(Clone, Debug, PartialEq, Eq)]
enum Transfer {
    Idle,
    /// A segmented download: what has come, how much will, the toggle bit expected next.
    Download {
        index: u16,
        sub: u8,
        size: usize,
        data: Vec<u8>,
        toggle: u8,
    },
}

/// The application side of one ESC's mailbox.
#[derive(Clone, Debug)]
pub struct Mailbox {
    transfer: Transfer,
    /// Counter of the replies this slave sends, 1..=7.
    counter: u8,
    outbox: VecDeque<Vec<u8>>,
    /// The reply last handed to SM1, for a master's repeat request.
    last: Option<Vec<u8>>,
}

impl Default for Mailbox {
    fn default() -> Self {
        Mailbox { transfer: Transfer::Idle, counter: 0, outbox: VecDeque::new(), last: None }
    }
}

impl Mailbox {
    /// A message the master wrote into SM0 (its whole window, `message`), answered into
    /// the outbox. In Init the slave has no mailbox: the message is read and dropped.
    pub fn receive(&mut self, message: &[u8], slave: &mut Slave) {
        let Some(head) = message.first_chunk::<MAILBOX_HEADER_LEN>().map(MailboxHeader::parse) else { return };
        let body = &message[MAILBOX_HEADER_LEN..];
        if usize::from(head.length) > body.len() {
            return self.error(MailboxError::InvalidSize);
        }
        let body = &body[..usize::from(head.length)];
        match MailboxType::try_from(head.type_code()) {
            Ok(MailboxType::Coe) => self.coe(body, slave),
            _ => self.error(MailboxError::UnsupportedProtocol),
        }
    }

    /// The next reply for SM1, if any; kept for a repeat request.
    pub fn next_reply(&mut self) -> Option<&[u8]> {
        let reply = self.outbox.pop_front()?;
        self.last = Some(reply);
        self.last.as_deref()
    }

    /// The reply last handed to SM1 (a master's repeat request wants it again).
    pub fn last_reply(&self) -> Option<&[u8]> {
        self.last.as_deref()
    }

    fn coe(&mut self, body: &[u8], slave: &mut Slave) {
        let Some(&[c0, c1]) = body.first_chunk::<2>() else { return self.error(MailboxError::SizeTooShort) };
        if u16::from_le_bytes([c0, c1]) >> 12 != COE_SDO_REQUEST {
            return self.error(MailboxError::ServiceNotSupported);
        }
        let Some(sdo) = body.first_chunk::<SDO_LEN>() else { return self.error(MailboxError::SizeTooShort) };
        let command = sdo[2];
        let index = u16::from_le_bytes([sdo[3], sdo[4]]);
        let sub = sdo[5];
        let data = [sdo[6], sdo[7], sdo[8], sdo[9]];
        match command & 0xE0 {
            CCS_INITIATE_UPLOAD if command & COMPLETE_ACCESS != 0 => {
                self.abort(index, sub, SdoAbort::UnsupportedAccess)
            }
            CCS_INITIATE_UPLOAD => self.upload(index, sub, slave),
            CCS_INITIATE_DOWNLOAD if command & COMPLETE_ACCESS != 0 => {
                self.abort(index, sub, SdoAbort::UnsupportedAccess)
            }
            CCS_INITIATE_DOWNLOAD => self.initiate_download(command, index, sub, data, &body[SDO_LEN..], slave),
            CCS_DOWNLOAD_SEGMENT => self.download_segment(command, &body[2..], slave),
            // No upload is ever segmented: every object fits an expedited reply.
            CCS_UPLOAD_SEGMENT => self.abort(index, sub, SdoAbort::UnknownCommand),
            CCS_ABORT => self.transfer = Transfer::Idle,
            _ => self.abort(index, sub, SdoAbort::UnknownCommand),
        }
    }

    /// Initiate upload: the value goes back expedited (every object is 1 to 4 bytes).
    fn upload(&mut self, index: u16, sub: u8, slave: &Slave) {
        self.transfer = Transfer::Idle;
        match slave.sdo_read(index, sub) {
            Ok((value, len)) => {
                let len = len.clamp(1, 4);
                let command = CCS_INITIATE_UPLOAD | ((4 - len as u8) << 2) | EXPEDITED | SIZE_INDICATED;
                let mut data = [0u8; 4];
                data[..len].copy_from_slice(&value.to_le_bytes()[..len]);
                self.sdo_response(command, index, sub, data);
            }
            Err(error) => self.failed(index, sub, error),
        }
    }

    fn initiate_download(&mut self, command: u8, index: u16, sub: u8, data: [u8; 4], rest: &[u8], slave: &mut Slave) {
        self.transfer = Transfer::Idle;
        if command & EXPEDITED != 0 {
            let len = if command & SIZE_INDICATED != 0 {
                4 - usize::from((command >> 2) & 0b11)
            } else {
                // Size unspecified: as many bytes as the object has.
                match slave.sdo_describe(index, sub) {
                    Ok(description) => description.ty.bytes().min(4),
                    Err(error) => return self.failed(index, sub, error),
                }
            };
            return self.write(index, sub, &data[..len], slave);
        }
        let size = u32::from_le_bytes(data) as usize;
        if command & SIZE_INDICATED == 0 || size > MAX_DOWNLOAD {
            return self.abort(index, sub, SdoAbort::LengthTooHigh);
        }
        if rest.len() >= size {
            return self.write(index, sub, &rest[..size], slave);
        }
        self.transfer = Transfer::Download { index, sub, size, data: rest.to_vec(), toggle: 0 };
        self.sdo_response(0x60, index, sub, [0; 4]);
    }

    /// A download segment: `segment` is the message from its command byte on.
    fn download_segment(&mut self, command: u8, segment: &[u8], slave: &mut Slave) {
        let Transfer::Download { index, sub, size, mut data, toggle } =
            std::mem::replace(&mut self.transfer, Transfer::Idle)
        else {
            return self.abort(0, 0, SdoAbort::UnknownCommand);
        };
        if command & TOGGLE != toggle {
            return self.abort(index, sub, SdoAbort::ToggleBit);
        }
        let bytes = &segment[1..];
        // A segment in the shortest message says how many of its 7 bytes are unused.
        let count = if bytes.len() == 7 { 7 - usize::from((command >> 1) & 0b111) } else { bytes.len() };
        data.extend_from_slice(&bytes[..count]);
        if data.len() > size {
            return self.abort(index, sub, SdoAbort::LengthTooHigh);
        }
        if command & LAST_SEGMENT == 0 {
            self.transfer = Transfer::Download { index, sub, size, data, toggle: toggle ^ TOGGLE };
            return self.segment_response(0x20 | toggle);
        }
        if data.len() != size {
            return self.abort(index, sub, SdoAbort::LengthTooLow);
        }
        match slave.sdo_write(index, sub, &data) {
            Ok(()) => self.segment_response(0x20 | toggle),
            Err(error) => self.failed(index, sub, error),
        }
    }

    fn write(&mut self, index: u16, sub: u8, data: &[u8], slave: &mut Slave) {
        match slave.sdo_write(index, sub, data) {
            Ok(()) => self.sdo_response(0x60, index, sub, [0; 4]),
            Err(error) => self.failed(index, sub, error),
        }
    }

    /// An SDO that did not happen: its abort; in Init no reply at all.
    fn failed(&mut self, index: u16, sub: u8, error: SdoError) {
        match error {
            SdoError::Abort(abort) => self.abort(index, sub, abort),
            SdoError::NoMailbox => {}
            // A slave behind an ESC is in memory: no wire's queue between them.
            SdoError::NoSlave(_) | SdoError::MailboxBusy | SdoError::Pending => {
                self.abort(index, sub, SdoAbort::General)
            }
        }
    }

    fn sdo_response(&mut self, command: u8, index: u16, sub: u8, data: [u8; 4]) {
        let [i0, i1] = index.to_le_bytes();
        let [d0, d1, d2, d3] = data;
        self.coe_reply(COE_SDO_RESPONSE, &[command, i0, i1, sub, d0, d1, d2, d3]);
    }

    fn segment_response(&mut self, command: u8) {
        self.coe_reply(COE_SDO_RESPONSE, &[command, 0, 0, 0, 0, 0, 0, 0]);
    }

    /// An abort goes as an SDO request (ETG.1000.6 5.6.2.7), with the CiA 301 code.
    fn abort(&mut self, index: u16, sub: u8, abort: SdoAbort) {
        self.transfer = Transfer::Idle;
        let [i0, i1] = index.to_le_bytes();
        let [d0, d1, d2, d3] = abort.code().to_le_bytes();
        self.coe_reply(COE_SDO_REQUEST, &[CCS_ABORT, i0, i1, sub, d0, d1, d2, d3]);
    }

    fn coe_reply(&mut self, service: u16, sdo: &[u8; 8]) {
        let mut body = (service << 12).to_le_bytes().to_vec();
        body.extend_from_slice(sdo);
        self.reply(MailboxType::Coe, &body);
    }

    fn error(&mut self, detail: MailboxError) {
        let mut body = 0x0001u16.to_le_bytes().to_vec();
        body.extend_from_slice(&(detail as u16).to_le_bytes());
        self.reply(MailboxType::Error, &body);
    }

    fn reply(&mut self, kind: MailboxType, body: &[u8]) {
        // The counter runs 1..=7; 0 is for a slave without it.
        self.counter = self.counter % 7 + 1;
        let head =
            MailboxHeader { length: body.len() as u16, address: 0, channel: 0, kind: kind as u8 | self.counter << 4 };
        let mut message = head.to_bytes().to_vec();
        message.extend_from_slice(body);
        if self.outbox.len() == OUTBOX_LEN {
            // The master has stopped fetching: the oldest reply goes.
            self.outbox.pop_front();
        }
        self.outbox.push_back(message);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use config::AxisConfig;
    use devices::drive::Drive;
    use devices::ecat::AlState;

    fn drive() -> Slave {
        let mut slave = Slave::new(Box::new(Drive::new(&AxisConfig::default())));
        slave.request_state(AlState::PreOp).unwrap();
        slave
    }

    /// A CoE SDO request as SOEM writes it: header, CoE service 2, command, index, sub, data.
    fn sdo(command: u8, index: u16, sub: u8, data: [u8; 4]) -> Vec<u8> {
        let [i0, i1] = index.to_le_bytes();
        let mut m = vec![10, 0, 0, 0, 0, 0x13, 0x00, 0x20, command, i0, i1, sub];
        m.extend_from_slice(&data);
        m
    }

    fn reply(mailbox: &mut Mailbox) -> Vec<u8> {
        mailbox.next_reply().expect("a reply").to_vec()
    }

    /// Expedited upload of 0x1000 (CoE manual table 4-1: 0x00020192), 0x6060 (8).
    #[test]
    fn an_expedited_upload_answers_with_the_value() {
        let (mut slave, mut mailbox) = (drive(), Mailbox::default());
        mailbox.receive(&sdo(0x40, 0x1000, 0, [0; 4]), &mut slave);
        assert_eq!(
            reply(&mut mailbox),
            [10, 0, 0, 0, 0, 0x13, 0x00, 0x30, 0x43, 0x00, 0x10, 0, 0x92, 0x01, 0x02, 0x00]
        );
        mailbox.receive(&sdo(0x40, 0x6060, 0, [0; 4]), &mut slave);
        assert_eq!(&reply(&mut mailbox)[5..13], [0x23, 0x00, 0x30, 0x4F, 0x60, 0x60, 0, 8], "counter 2, 1 byte");
    }

    /// The aborts of the CoE manual's dictionary, carried as SDO requests.
    #[test]
    fn a_refused_sdo_is_aborted_with_the_dictionary_s_code() {
        let (mut slave, mut mailbox) = (drive(), Mailbox::default());
        let rows: [(Vec<u8>, u32); 5] = [
            (sdo(0x40, 0x6011, 0, [0; 4]), 0x0602_0000),
            (sdo(0x2B, 0x1018, 1, [0; 4]), 0x0601_0002),
            (sdo(0x23, 0x6040, 0, [0; 4]), 0x0607_0012),
            (sdo(0x50, 0x1018, 0, [0; 4]), 0x0601_0000),
            (sdo(0xE0, 0x1018, 0, [0; 4]), 0x0504_0001),
        ];
        for (request, code) in rows {
            mailbox.receive(&request, &mut slave);
            let answer = reply(&mut mailbox);
            assert_eq!((answer[7], answer[8]), (0x20, 0x80), "an abort request");
            assert_eq!(u32::from_le_bytes(answer[12..16].try_into().unwrap()), code);
        }
    }

    /// Expedited download of 0x6060, then a segmented one of 0x607A: init with 0 bytes, two
    /// segments with the toggle bit.
    #[test]
    fn downloads_expedited_and_segmented() {
        let (mut slave, mut mailbox) = (drive(), Mailbox::default());
        mailbox.receive(&sdo(0x2F, 0x6060, 0, [1, 0, 0, 0]), &mut slave);
        assert_eq!(&reply(&mut mailbox)[6..10], [0x00, 0x30, 0x60, 0x60]);
        assert_eq!(slave.sdo_read(0x6060, 0), Ok((1, 1)));

        mailbox.receive(&sdo(0x21, 0x607A, 0, [4, 0, 0, 0]), &mut slave);
        assert_eq!(reply(&mut mailbox)[8], 0x60);
        let segment = |command, bytes: &[u8]| {
            let mut m = vec![10, 0, 0, 0, 0, 0x13, 0x00, 0x20, command];
            m.extend_from_slice(bytes);
            m
        };
        // 2 bytes of 7 used: n = 5.
        mailbox.receive(&segment(5 << 1, &[0x40, 0x42, 0, 0, 0, 0, 0]), &mut slave);
        assert_eq!(reply(&mut mailbox)[8], 0x20);
        mailbox.receive(&segment(0x10 | 5 << 1 | 1, &[0x0F, 0x00, 0, 0, 0, 0, 0]), &mut slave);
        assert_eq!(reply(&mut mailbox)[8], 0x30, "the last segment, toggle 1");
        assert_eq!(slave.sdo_read(0x607A, 0), Ok((1_000_000, 4)));
    }

    /// Wrong toggle, a segment with no transfer, wrong lengths, other protocols.
    #[test]
    fn messages_the_mailbox_cannot_take() {
        let (mut slave, mut mailbox) = (drive(), Mailbox::default());
        let segment = vec![10, 0, 0, 0, 0, 0x13, 0x00, 0x20, 0x10, 0, 0, 0, 0, 0, 0, 0];
        mailbox.receive(&segment, &mut slave);
        assert_eq!(u32::from_le_bytes(reply(&mut mailbox)[12..16].try_into().unwrap()), 0x0504_0001);
        mailbox.receive(&sdo(0x21, 0x607A, 0, [4, 0, 0, 0]), &mut slave);
        reply(&mut mailbox);
        mailbox.receive(&segment, &mut slave);
        assert_eq!(u32::from_le_bytes(reply(&mut mailbox)[12..16].try_into().unwrap()), 0x0503_0000, "toggle 1 first");
        let error = |mailbox: &mut Mailbox| {
            let answer = reply(mailbox);
            assert_eq!(answer[5] & 0x0F, 0, "a mailbox error reply");
            u16::from_le_bytes([answer[8], answer[9]])
        };
        let mut long = sdo(0x40, 0x1000, 0, [0; 4]);
        long[0] = 200;
        mailbox.receive(&long, &mut slave);
        assert_eq!(error(&mut mailbox), MailboxError::InvalidSize as u16);
        let mut short = sdo(0x40, 0x1000, 0, [0; 4]);
        short[0] = 4;
        mailbox.receive(&short, &mut slave);
        assert_eq!(error(&mut mailbox), MailboxError::SizeTooShort as u16);
        let mut foe = sdo(0x40, 0x1000, 0, [0; 4]);
        foe[5] = 0x14;
        mailbox.receive(&foe, &mut slave);
        assert_eq!(error(&mut mailbox), MailboxError::UnsupportedProtocol as u16);
        let mut info = sdo(0x40, 0x1000, 0, [0; 4]);
        info[7] = 0x80;
        mailbox.receive(&info, &mut slave);
        assert_eq!(error(&mut mailbox), MailboxError::ServiceNotSupported as u16);
        mailbox.receive(&[1, 2], &mut slave);
        assert!(mailbox.next_reply().is_none(), "no header: nothing to answer");
    }

    /// CoE manual table 2-3: no mailbox in Init.
    #[test]
    fn in_init_a_message_is_dropped() {
        let mut slave = Slave::new(Box::new(Drive::new(&AxisConfig::default())));
        let mut mailbox = Mailbox::default();
        mailbox.receive(&sdo(0x40, 0x1000, 0, [0; 4]), &mut slave);
        assert!(mailbox.next_reply().is_none());
    }
}
