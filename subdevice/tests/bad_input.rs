//! Issue 38 item 3: bad input on the wire. None of it may panic the segment or corrupt a
//! drive; each gets what an ESC does: the frame ignored, or the working counter left.

mod bench;

use bench::*;
use subdevice::frame::FrameError;
use subdevice::registers::AL_STATUS;

/// The drive's identity and type straight from its dictionary: the objects no master may
/// change (CoE manual table 4-1).
fn identity(bench: &Bench, n: usize) -> Vec<i64> {
    let od = bench.segment.escs()[n].slave().device().od();
    [(0x1000, 0), (0x1018, 1), (0x1018, 2), (0x1018, 3)].iter().map(|&(i, s)| od.get(od.find(i, s).unwrap())).collect()
}

/// Truncated frames and datagrams claiming more than the frame: dropped, untouched.
#[test]
fn broken_frames_are_dropped_untouched() {
    let mut bench = Bench::drives(2);
    bench.address_all();
    let good = frame(&[datagram(FPWR, station(0), 0x0120, vec![0x02, 0x00])]);
    let mut past = good.clone();
    past[16 + 6] = 0xFF; // the datagram claims 255 bytes
    let rows: [(&str, Vec<u8>, FrameError); 4] = [
        (
            "cut in its datagram",
            good[..good.len() - 3].to_vec(),
            FrameError::LengthPastFrame { claimed: 14, available: 11 },
        ),
        ("cut in the EtherCAT header", good[..15].to_vec(), FrameError::TooShort(15)),
        ("a datagram past the frame", past, FrameError::DatagramPastFrame { datagram: 0, needed: 267, available: 14 }),
        ("no datagram", [&ETHERNET[..], &[0x00, 0x10]].concat(), FrameError::NoDatagram),
    ];
    for (what, bytes, error) in rows {
        let mut sent = bytes.clone();
        assert_eq!(bench.segment.process(&mut sent, bench.now), Err(error), "{what}");
        assert_eq!(sent, bytes, "{what}: nothing changed");
    }
    assert_eq!(bench.al_status(0), (0x01, 0), "the AL control write of the broken frames never happened");
}

/// An unknown command passes every ESC untouched, its WKC too; the datagrams around it
/// are processed.
#[test]
fn an_unknown_command_passes_untouched() {
    let mut bench = Bench::drives(2);
    for code in [0x0F, 0x10, 0x7F, 0xFF] {
        let answers = bench.exchange(&[
            datagram(BRD, 0, 0x0000, vec![0; 2]),
            datagram(code, 0, 0x0120, vec![0x08, 0x00]),
            datagram(BRD, 0, 0x0130, vec![0; 2]),
        ]);
        assert_eq!(answers[1].wkc, 0, "0x{code:02X}");
        assert_eq!(answers[1].data, [0x08, 0x00], "0x{code:02X}: data as sent");
        assert_eq!(answers[1].header.adp(), 0, "0x{code:02X}: not counted up");
        assert_eq!((answers[0].wkc, answers[2].wkc), (2, 2));
        assert_eq!(answers[2].data, [0x01, 0x00], "still Init");
    }
}

/// Writes to registers the ESC protects: the register keeps its value; the datagram
/// counts, as any register access does (docs/decisions.md, "Protected registers").
#[test]
fn protected_registers_keep_their_value() {
    let mut bench = Bench::drives(1);
    bench.address_all();
    let rows: [(u16, usize, &str); 6] = [
        (0x0000, 8, "type, revision, build, FMMUs, SMs, RAM, ports"),
        (0x0008, 2, "features"),
        (0x0012, 2, "station alias (from the SII)"),
        (0x0110, 2, "DL status"),
        (0x0130, 6, "AL status and its code"),
        (0x0805, 1, "SM0 status"),
    ];
    for (ado, len, what) in rows {
        let (before, _) = bench.fprd(0, ado, len);
        assert_eq!(bench.fpwr(0, ado, &vec![0xA5; len]), 1, "{what}: the write counts");
        assert_eq!(bench.fprd(0, ado, len).0, before, "{what}: unchanged");
    }
    assert_eq!(bench.al_status(0), (0x01, 0));
}

/// Mailbox messages whose header lies about their length: a mailbox error reply, no SDO,
/// and the mailbox goes on working.
#[test]
fn a_mailbox_message_with_a_wrong_length() {
    let mut bench = Bench::drives(1);
    bench.address_all();
    bench.configure_mailbox(0);
    bench.request(0, 0x02);
    let before = bench.upload(0, 0x6060, 0);
    // An expedited download of 0x6060 = 1, its length 300 (past the mailbox) or 4.
    for (length, detail) in [(300u16, 0x08u16), (4, 0x06)] {
        let [l0, l1] = length.to_le_bytes();
        let reply = bench.mailbox(0, &[l0, l1, 0, 0, 0, 0x03, 0x00, 0x20, 0x2F, 0x60, 0x60, 0, 1, 0, 0, 0]);
        assert_eq!(reply[5] & 0x0F, 0, "length {length}: a mailbox error reply");
        assert_eq!(u16::from_le_bytes([reply[8], reply[9]]), detail, "length {length}");
    }
    assert_eq!(bench.upload(0, 0x6060, 0), before, "nothing was written");
    assert_eq!(bench.upload(0, 0x6060, 0), Ok(vec![8]));
}

/// A seeded xorshift: the same frames every run.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }

    fn bytes(&mut self, n: usize) -> Vec<u8> {
        (0..n).map(|_| self.next() as u8).collect()
    }
}

/// One random frame: half of them random bytes after an EtherCAT header, half well
/// formed with random commands, addresses and data, some with a length that lies.
fn random_frame(random: &mut Random) -> Vec<u8> {
    if random.below(2) == 0 {
        let mut bytes = ETHERNET.to_vec();
        let len = random.below(120) as usize;
        bytes.extend(random.bytes(len));
        return bytes;
    }
    let count = 1 + random.below(4) as usize;
    let datagrams: Vec<Datagram> = (0..count)
        .map(|_| {
            let command = random.below(16) as u8;
            let adp = match random.below(3) {
                0 => random.below(4) as u16,
                1 => station(random.below(3) as usize),
                _ => random.next() as u16,
            };
            let ado = match random.below(4) {
                0 => random.below(0x1000) as u16,
                1 => 0x0100 + random.below(0x900) as u16,
                2 => 0x1000 + random.below(0x1000) as u16,
                _ => random.next() as u16,
            };
            let len = random.below(48) as usize;
            datagram(command, adp, ado, random.bytes(len))
        })
        .collect();
    let mut bytes = frame(&datagrams);
    if random.below(8) == 0 {
        let at = 16 + 6;
        bytes[at] = random.next() as u8;
    }
    bytes
}

/// 100 000 random frames at a segment in Op: no panic, every frame answered in place or
/// dropped, each ESC's AL status its slave's state, no drive's identity changed.
#[test]
fn a_burst_of_random_frames() {
    let mut bench = Bench::drives(2);
    bench.bring_up();
    let identities = [identity(&bench, 0), identity(&bench, 1)];
    let mut random = Random(0x9E37_79B9_7F4A_7C15);
    let (mut answered, mut dropped) = (0, 0);
    for _ in 0..100_000 {
        let mut bytes = random_frame(&mut random);
        let len = bytes.len();
        bench.now += 50_000;
        match bench.segment.process(&mut bytes, bench.now) {
            Ok(()) => answered += 1,
            Err(_) => dropped += 1,
        }
        assert_eq!(bytes.len(), len);
    }
    assert!(answered > 10_000 && dropped > 10_000, "both kinds met: {answered} answered, {dropped} dropped");
    for (n, esc) in bench.segment.escs().iter().enumerate() {
        let state = u16::from(esc.slave().esm().state().code());
        assert_eq!(esc.registers().u16(AL_STATUS) & 0x0F, state, "slave {n}");
        assert_eq!(identity(&bench, n), identities[n], "slave {n}");
    }
    let answer = bench.one(datagram(BRD, 0, 0x0000, vec![0; 1]));
    assert_eq!((answer.wkc, answer.data[0]), (2, 0x04), "the segment still answers");
}
