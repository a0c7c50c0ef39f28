//! The segment as a master meets it: scan, addressing, SII, ESM, mailbox, process data,
//! distributed clock, each with byte literals.

mod bench;

use bench::*;

/// A BRD of the type register counts the ESCs (SOEM's `ecx_detect_slaves`); each
/// position command counts ADP up as the frame passes.
#[test]
fn a_broadcast_read_counts_the_slaves_and_positions_count_up() {
    let mut bench = Bench::drives(3);
    let a = bench.one(datagram(BRD, 0, 0x0000, vec![0, 0]));
    assert_eq!((a.wkc, a.data.as_slice()), (3, &[0x04, 0x01][..]), "type 0x04, revision 1");
    assert_eq!(a.header.adp(), 3, "incremented by each slave");
    bench.address_all();
    assert_eq!(bench.fprd(2, 0x0010, 2), (station(2).to_le_bytes().to_vec(), 1));
    let a = bench.one(datagram(APRD, 0xFFFF, 0x0010, vec![0, 0]));
    assert_eq!((a.data, a.wkc), (station(1).to_le_bytes().to_vec(), 1), "position -1 is the second slave");
    assert_eq!(bench.fprd(7, 0x0010, 2).1, 0, "no slave at that address");
}

/// Several datagrams in one frame, each with its own working counter.
#[test]
fn datagrams_of_one_frame_are_answered_each() {
    let mut bench = Bench::drives(2);
    bench.address_all();
    let answers = bench.exchange(&[
        datagram(FPRD, station(0), 0x0130, vec![0; 2]),
        datagram(BRD, 0, 0x0130, vec![0; 2]),
        datagram(FPRD, station(1), 0x0110, vec![0; 2]),
    ]);
    assert_eq!(answers.iter().map(|a| a.wkc).collect::<Vec<_>>(), [1, 2, 1]);
    assert_eq!(answers[0].data, [0x01, 0x00], "Init");
    assert_eq!(answers[2].data[1] & 0x0F, 0x06, "the last slave: port 0 open, port 1 closed");
    assert_eq!(answers[0].header.index, 0);
    assert_eq!(answers[2].header.index, 2);
}

/// The SII read protocol: address and read command into 0x0502, 8 bytes from 0x0508:
/// the identity of 0x1018 (CoE manual table 4-1: vendor 0xAAAA; table 4-2: D1 is 2).
#[test]
fn the_eeprom_holds_the_identity_of_0x1018() {
    let mut bench = Bench::drives(1);
    bench.address_all();
    assert_eq!(bench.fpwr(0, 0x0502, &[0x00, 0x01, 0x08, 0x00, 0x00, 0x00]), 1);
    let (status, _) = bench.fprd(0, 0x0502, 2);
    assert_eq!(status, [0x40, 0x00], "8-byte reads, not busy, no error");
    assert_eq!(bench.fprd(0, 0x0508, 8).0, [0xAA, 0xAA, 0, 0, 2, 0, 0, 0]);
    bench.fpwr(0, 0x0502, &[0x00, 0x01, 0x1C, 0x00, 0x00, 0x00]);
    assert_eq!(bench.fprd(0, 0x0508, 2).0, [0x04, 0x00], "mailbox protocols: CoE");
}

/// CoE manual table 2-3: Init to PreOp needs the mailbox SyncManagers; refused, the AL
/// status shows the error bit and ETG.1000.6's code until a request acknowledges it.
#[test]
fn the_esm_checks_the_mailbox_and_shows_refusals() {
    let mut bench = Bench::drives(1);
    bench.address_all();
    bench.request(0, 0x02);
    assert_eq!(bench.al_status(0), (0x11, 0x0016), "Init, error: invalid mailbox configuration");
    bench.configure_mailbox(0);
    bench.request(0, 0x02);
    assert_eq!(bench.al_status(0), (0x11, 0x0016), "no acknowledge: still refused");
    bench.request(0, 0x12);
    assert_eq!(bench.al_status(0), (0x02, 0));
    bench.request(0, 0x08);
    assert_eq!(bench.al_status(0), (0x12, 0x0011), "the slave's own ESM: no skipping");
    bench.request(0, 0x14);
    assert_eq!(bench.al_status(0), (0x12, 0x0030), "DC mode without SYNC0 activation (the drive's default)");
    bench.request(0, 0x13);
    assert_eq!(bench.al_status(0), (0x12, 0x0013), "no bootstrap");
    bench.request(0, 0x01);
    assert_eq!(bench.al_status(0), (0x01, 0), "down is always taken");
}

/// SDOs through SM0/SM1 are the slave's own: the CoE manual's values and aborts.
#[test]
fn sdos_through_the_mailbox() {
    let mut bench = Bench::drives(1);
    bench.address_all();
    bench.configure_mailbox(0);
    bench.request(0, 0x12);
    assert_eq!(bench.upload(0, 0x1000, 0), Ok(0x0002_0192u32.to_le_bytes().to_vec()));
    assert_eq!(bench.upload(0, 0x6502, 0), Ok(0x03ADu32.to_le_bytes().to_vec()));
    assert_eq!(bench.upload(0, 0x6060, 0), Ok(vec![8]));
    assert_eq!(bench.upload(0, 0x6011, 0), Err(0x0602_0000));
    assert_eq!(bench.download(0, 0x1018, 1, &[1, 0, 0, 0]), Err(0x0601_0002));
    assert_eq!(bench.download(0, 0x6060, 0, &[1]), Ok(()));
    assert_eq!(bench.upload(0, 0x6060, 0), Ok(vec![1]));
    let (_, wkc) = bench.fprd(0, 0x18F6, 246);
    assert_eq!(wkc, 0, "an empty mailbox cannot be read");
}

/// Bring-up to Op, then CiA 402 through LRW: the controlword goes out, the statusword
/// comes back, the working counter is 3 per slave.
#[test]
fn process_data_through_lrw() {
    let mut bench = Bench::drives(2);
    bench.bring_up();
    let mut image = vec![0u8; 32];
    let exchange = |bench: &mut Bench, image: &mut Vec<u8>| {
        let a = bench.one(Datagram { command: LRW, address: 0, data: image.clone() });
        assert_eq!(a.wkc, 6, "3 per slave: read and written");
        *image = a.data;
    };
    let statusword = |image: &[u8], n: usize| u16::from_le_bytes([image[12 + 10 * n], image[13 + 10 * n]]);
    exchange(&mut bench, &mut image);
    assert_eq!(statusword(&image, 0), 0, "free run: the slave steps after the first frame");
    exchange(&mut bench, &mut image);
    assert_eq!(statusword(&image, 0) & 0x6F, 0x40, "Switch on disabled");
    for controlword in [0x06u16, 0x07, 0x0F] {
        for n in 0..2 {
            image[6 * n..6 * n + 2].copy_from_slice(&controlword.to_le_bytes());
        }
        exchange(&mut bench, &mut image);
        exchange(&mut bench, &mut image);
    }
    assert_eq!(statusword(&image, 0) & 0x6F, 0x27, "Operation enabled");
    assert_eq!(statusword(&image, 1) & 0x6F, 0x27);
}

/// SOEM's `config_dc`: a BWR to 0x0900 latches each port's receive time; the delays along
/// the line come out of port 1 minus port 0; the offset brings system time to the master's.
#[test]
fn the_distributed_clock_latches_and_follows_the_reference() {
    let mut bench = Bench::drives(3);
    bench.address_all();
    let a = bench.one(datagram(BWR, 0, 0x0900, vec![0; 4]));
    assert_eq!(a.wkc, 3);
    let times: Vec<[u32; 2]> = (0..3)
        .map(|n| {
            let (d, _) = bench.fprd(n, 0x0900, 8);
            [u32::from_le_bytes(d[0..4].try_into().unwrap()), u32::from_le_bytes(d[4..8].try_into().unwrap())]
        })
        .collect();
    assert_eq!(times[0][1].wrapping_sub(times[0][0]), 4 * 500, "two hops out and back after the first");
    assert_eq!(times[1][1].wrapping_sub(times[1][0]), 2 * 500);
    assert_eq!(times[2][1], 0, "port 1 closed");
    let (features, _) = bench.fprd(0, 0x0008, 2);
    assert_eq!(features[0] & 0x04, 0x04, "DC supported");
    // Each slave's offset to system time 0 at the latch; the reference distributed by FRMW.
    for n in 0..3 {
        let (receive, _) = bench.fprd(n, 0x0918, 8);
        let offset = u64::from_le_bytes(receive.try_into().unwrap()).wrapping_neg();
        bench.fpwr(n, 0x0920, &offset.to_le_bytes());
        bench.fpwr(n, 0x0928, &(n as u32 * 500).to_le_bytes());
    }
    let a = bench.one(datagram(FRMW, station(0), 0x0910, vec![0; 8]));
    assert_eq!(a.wkc, 3, "one read, two writes");
    let reference = u64::from_le_bytes(a.data.try_into().unwrap());
    let (diff, _) = bench.fprd(2, 0x092C, 4);
    assert_eq!(u32::from_le_bytes(diff.try_into().unwrap()), 0x8000_0000 | 1_000, "behind by its delay");
    let a = bench.one(datagram(FRMW, station(0), 0x0910, vec![0; 8]));
    let (diff, _) = bench.fprd(2, 0x092C, 4);
    assert_eq!(u32::from_le_bytes(diff.try_into().unwrap()) & 0x7FFF_FFFF, 0, "in step after one compare");
    assert!(u64::from_le_bytes(a.data.try_into().unwrap()) > reference);
}
