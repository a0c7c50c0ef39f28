//! A master of byte literals over a segment of simulated drives: datagrams are built as
//! ETG.1000.4 lays them out, sent through `Segment::process` and read back.

#![allow(dead_code)]

use config::AxisConfig;
use devices::ecat::Network;
use subdevice::frame::{DATAGRAM_HEADER_LEN, DatagramHeader};
use subdevice::{Esc, Segment};

/// SOEM's Ethernet header: broadcast, from 01:01:01:01:01:01.
pub const ETHERNET: [u8; 14] = [0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 1, 1, 1, 1, 1, 1, 0x88, 0xA4];

/// Command codes (ETG.1000.4 5.4).
pub const APRD: u8 = 1;
pub const APWR: u8 = 2;
pub const FPRD: u8 = 4;
pub const FPWR: u8 = 5;
pub const BRD: u8 = 7;
pub const BWR: u8 = 8;
pub const LRW: u8 = 12;
pub const FRMW: u8 = 14;

/// One datagram to send: command, ADP/ADO (or the logical address), data.
#[derive(Clone, Debug)]
pub struct Datagram {
    pub command: u8,
    pub address: u32,
    pub data: Vec<u8>,
}

pub fn datagram(command: u8, adp: u16, ado: u16, data: Vec<u8>) -> Datagram {
    Datagram { command, address: u32::from(adp) | u32::from(ado) << 16, data }
}

/// What came back of one datagram.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Answer {
    pub header: DatagramHeader,
    pub data: Vec<u8>,
    pub wkc: u16,
}

/// The Ethernet frame of `datagrams`, the `M` bit on all but the last.
pub fn frame(datagrams: &[Datagram]) -> Vec<u8> {
    let mut body = Vec::new();
    for (i, d) in datagrams.iter().enumerate() {
        let header = DatagramHeader {
            command: d.command,
            index: i as u8,
            address: d.address,
            length: d.data.len() as u16,
            circulating: false,
            more: i + 1 < datagrams.len(),
            irq: 0,
        };
        let mut bytes = [0u8; DATAGRAM_HEADER_LEN];
        header.write(&mut bytes);
        body.extend_from_slice(&bytes);
        body.extend_from_slice(&d.data);
        body.extend_from_slice(&[0, 0]);
    }
    let mut frame = ETHERNET.to_vec();
    frame.extend_from_slice(&((body.len() as u16) | 0x1000).to_le_bytes());
    frame.extend_from_slice(&body);
    frame
}

/// The datagrams of a returned frame.
pub fn answers(frame: &[u8]) -> Vec<Answer> {
    let mut answers = Vec::new();
    let mut at = 16;
    loop {
        let header = DatagramHeader::parse(frame[at..at + 10].try_into().unwrap());
        let len = usize::from(header.length);
        let data = frame[at + 10..at + 10 + len].to_vec();
        let wkc = u16::from_le_bytes([frame[at + 10 + len], frame[at + 11 + len]]);
        answers.push(Answer { header, data, wkc });
        at += 12 + len;
        if !header.more {
            return answers;
        }
    }
}

/// A segment of drives and a clock.
pub struct Bench {
    pub segment: Segment,
    pub now: u64,
}

/// Station address the bench gives slave `n` (SOEM's: 0x1001 on).
pub fn station(n: usize) -> u16 {
    0x1001 + n as u16
}

impl Bench {
    /// `count` D1 drives of the default axis.
    pub fn drives(count: usize) -> Self {
        let axes = vec![AxisConfig::default(); count];
        let escs = Network::new(&axes)
            .into_slaves()
            .into_iter()
            .enumerate()
            .map(|(i, slave)| Esc::new(slave, "HIWIN D1 CoE drive", 1_000_000_007 * (i as u64 + 1)))
            .collect();
        Bench { segment: Segment::new(escs), now: 1_000_000 }
    }

    /// One frame through the segment, 100 µs after the last.
    pub fn exchange(&mut self, datagrams: &[Datagram]) -> Vec<Answer> {
        let mut bytes = frame(datagrams);
        self.now += 100_000;
        self.segment.process(&mut bytes, self.now).expect("a well-formed frame");
        answers(&bytes)
    }

    pub fn one(&mut self, d: Datagram) -> Answer {
        self.exchange(&[d]).remove(0)
    }

    pub fn fprd(&mut self, n: usize, ado: u16, len: usize) -> (Vec<u8>, u16) {
        let a = self.one(datagram(FPRD, station(n), ado, vec![0; len]));
        (a.data, a.wkc)
    }

    pub fn fpwr(&mut self, n: usize, ado: u16, data: &[u8]) -> u16 {
        self.one(datagram(FPWR, station(n), ado, data.to_vec())).wkc
    }

    pub fn al_status(&mut self, n: usize) -> (u16, u16) {
        let (d, _) = self.fprd(n, 0x0130, 6);
        (u16::from_le_bytes([d[0], d[1]]), u16::from_le_bytes([d[4], d[5]]))
    }

    /// Station addresses by position, as a master's scan gives them.
    pub fn address_all(&mut self) {
        for n in 0..self.segment.escs().len() {
            let adp = (n as u16).wrapping_neg();
            self.one(datagram(APWR, adp, 0x0010, station(n).to_le_bytes().to_vec()));
        }
    }

    /// SM0 and SM1 as the SII gives them.
    pub fn configure_mailbox(&mut self, n: usize) {
        let sms = [0x00, 0x18, 0xF6, 0x00, 0x26, 0x00, 0x01, 0x00, 0xF6, 0x18, 0xF6, 0x00, 0x22, 0x00, 0x01, 0x00];
        self.fpwr(n, 0x0800, &sms);
    }

    pub fn request(&mut self, n: usize, state: u16) {
        self.fpwr(n, 0x0120, &state.to_le_bytes());
    }

    /// An SDO through the mailbox: the request written into SM0, the reply read from SM1.
    pub fn mailbox(&mut self, n: usize, request: &[u8]) -> Vec<u8> {
        let mut message = request.to_vec();
        message.resize(246, 0);
        assert_eq!(self.fpwr(n, 0x1800, &message), 1, "SM0 took the message");
        let (status, _) = self.fprd(n, 0x080D, 1);
        assert_eq!(status[0] & 0x08, 0x08, "a reply waits in SM1");
        let (reply, wkc) = self.fprd(n, 0x18F6, 246);
        assert_eq!(wkc, 1);
        reply
    }

    /// SDO upload: the value's bytes, or the abort code.
    pub fn upload(&mut self, n: usize, index: u16, sub: u8) -> Result<Vec<u8>, u32> {
        let [i0, i1] = index.to_le_bytes();
        let reply = self.mailbox(n, &[10, 0, 0, 0, 0, 0x03, 0x00, 0x20, 0x40, i0, i1, sub, 0, 0, 0, 0]);
        sdo_result(&reply).map(|()| reply[12..16 - usize::from((reply[8] >> 2) & 3)].to_vec())
    }

    /// SDO expedited download.
    pub fn download(&mut self, n: usize, index: u16, sub: u8, data: &[u8]) -> Result<(), u32> {
        let [i0, i1] = index.to_le_bytes();
        let command = 0x23 | ((4 - data.len() as u8) << 2);
        let mut request = vec![10, 0, 0, 0, 0, 0x03, 0x00, 0x20, command, i0, i1, sub];
        request.extend_from_slice(data);
        request.resize(16, 0);
        sdo_result(&self.mailbox(n, &request))
    }

    /// Every drive to PreOp, free run (0x1C32:01 = 0), the default mapping's SM2 (6 bytes)
    /// and SM3 (10 bytes), FMMU 0 for outputs at logical 16n, FMMU 1 for inputs after all
    /// outputs, SafeOp, Op.
    pub fn bring_up(&mut self) {
        self.address_all();
        let count = self.segment.escs().len();
        for n in 0..count {
            self.configure_mailbox(n);
            self.request(n, 0x02);
            assert_eq!(self.al_status(n), (0x02, 0), "slave {n} in PreOp");
            self.download(n, 0x1C32, 1, &[0, 0]).expect("free run");
            let sm2 = [0x00, 0x10, 6, 0, 0x64, 0, 1, 0];
            let sm3 = [0x00, 0x11, 10, 0, 0x20, 0, 1, 0];
            self.fpwr(n, 0x0810, &[sm2, sm3].concat());
            let out = (6 * n as u32).to_le_bytes();
            let inp = (6 * count as u32 + 10 * n as u32).to_le_bytes();
            let fmmu0 = [out[0], out[1], out[2], out[3], 6, 0, 0, 7, 0x00, 0x10, 0, 2, 1, 0, 0, 0];
            let fmmu1 = [inp[0], inp[1], inp[2], inp[3], 10, 0, 0, 7, 0x00, 0x11, 0, 1, 1, 0, 0, 0];
            self.fpwr(n, 0x0600, &[fmmu0, fmmu1].concat());
            self.request(n, 0x04);
            assert_eq!(self.al_status(n), (0x04, 0), "slave {n} in SafeOp");
            self.request(n, 0x08);
            assert_eq!(self.al_status(n), (0x08, 0), "slave {n} in Op");
        }
    }
}

/// The reply of an SDO: Ok for a response, the abort code for an abort.
pub fn sdo_result(reply: &[u8]) -> Result<(), u32> {
    assert_eq!(reply[5] & 0x0F, 3, "a CoE reply: {reply:02X?}");
    if reply[8] == 0x80 { Err(u32::from_le_bytes(reply[12..16].try_into().unwrap())) } else { Ok(()) }
}
