//! Property tests of serial port 1's decoders (DXMC 8.2, 8.3): Modbus RTU and ASCII frames
//! and FreePort framing (shared with `FreePort.Eth`). Whatever arrives, no decoder panics,
//! what it hands on is well formed, its buffers stay bounded, and after bad input the next
//! good frame is read as if nothing had come before it. 10^4 cases each, new ones every
//! run; a failure prints its smallest input, which becomes a regression row beside the
//! unit tests of the decoder.

use proptest::prelude::*;
use serial::ascii;
use serial::framing::{Deframer, Framing, Received};
use serial::rtu::{self, Request};

fn config() -> ProptestConfig {
    ProptestConfig { cases: 10_000, failure_persistence: None, ..ProptestConfig::default() }
}

/// `bytes` cut at the given points, in order (each point taken modulo the length).
fn chunks(bytes: &[u8], cuts: &[usize]) -> Vec<Vec<u8>> {
    let mut points: Vec<usize> = cuts.iter().map(|c| c % (bytes.len() + 1)).collect();
    points.extend([0, bytes.len()]);
    points.sort_unstable();
    points.windows(2).map(|w| bytes[w[0]..w[1]].to_vec()).collect()
}

/// A request whose length its function code gives (FC 03, 06, 16 with a right byte count).
fn rtu_request() -> impl Strategy<Value = Request> {
    let fixed = (prop_oneof![Just(0x03u8), Just(0x06u8)], any::<[u8; 4]>()).prop_map(|(f, b)| [&[f][..], &b].concat());
    let multiple = (any::<[u8; 4]>(), proptest::collection::vec(any::<u8>(), 0..=246))
        .prop_map(|(head, data)| [&[0x10][..], &head, &[data.len() as u8], &data].concat());
    (any::<u8>(), prop_oneof![fixed, multiple]).prop_map(|(address, pdu)| Request { address, pdu })
}

fn ascii_request() -> impl Strategy<Value = Request> {
    (any::<u8>(), proptest::collection::vec(any::<u8>(), 1..=250)).prop_map(|(address, pdu)| Request { address, pdu })
}

proptest! {
    #![proptest_config(config())]

    /// Any bytes, in any chunks, then silence: every request handed on is a frame with a
    /// good CRC of at most 256 bytes, and silence leaves the assembler empty.
    #[test]
    fn rtu_garbage_gives_only_good_frames(bytes in proptest::collection::vec(any::<u8>(), 0..280),
                                          cuts in proptest::collection::vec(any::<usize>(), 0..8)) {
        let mut assembler = rtu::Assembler::default();
        let mut got: Vec<Request> = Vec::new();
        for chunk in chunks(&bytes, &cuts) {
            got.extend(assembler.push(&chunk));
        }
        got.extend(assembler.silence());
        prop_assert!(assembler.is_empty());
        for request in got {
            let frame = rtu::frame(request.address, &request.pdu);
            prop_assert!(frame.len() <= rtu::MAX_FRAME && !request.pdu.is_empty(), "{frame:02X?}");
        }
    }

    /// Requests back to back, cut anywhere, are read back whole and in order; after
    /// garbage and a silence the next request is read alone.
    #[test]
    fn rtu_requests_survive_any_chunking(requests in proptest::collection::vec(rtu_request(), 1..6),
                                         cuts in proptest::collection::vec(any::<usize>(), 0..8),
                                         garbage in proptest::collection::vec(any::<u8>(), 0..100)) {
        let line: Vec<u8> = requests.iter().flat_map(|r| rtu::frame(r.address, &r.pdu)).collect();
        let mut assembler = rtu::Assembler::default();
        let mut got = Vec::new();
        for chunk in chunks(&line, &cuts) {
            got.extend(assembler.push(&chunk));
        }
        got.extend(assembler.silence());
        prop_assert_eq!(&got, &requests);
        assembler.push(&garbage);
        assembler.silence();
        let next = &requests[0];
        let mut after = assembler.push(&rtu::frame(next.address, &next.pdu));
        after.extend(assembler.silence());
        prop_assert_eq!(after, vec![next.clone()]);
    }

    /// Any bytes: every request handed on has a good LRC, and a good frame after them is
    /// read (its `:` starts afresh whatever came before).
    #[test]
    fn ascii_garbage_then_a_frame(bytes in proptest::collection::vec(any::<u8>(), 0..1200),
                                  cuts in proptest::collection::vec(any::<usize>(), 0..8),
                                  request in ascii_request()) {
        let mut assembler = ascii::Assembler::default();
        for chunk in chunks(&bytes, &cuts) {
            for got in assembler.push(&chunk) {
                let frame = [&[got.address][..], &got.pdu].concat();
                prop_assert!(!got.pdu.is_empty() && frame.len() <= 256, "{frame:02X?}");
            }
        }
        let good = ascii::frame(request.address, &request.pdu);
        prop_assert_eq!(assembler.push(&good), vec![request]);
    }

    /// Frames with anything but a `:` between them are all read, in any chunks.
    #[test]
    fn ascii_frames_between_noise(requests in proptest::collection::vec(ascii_request(), 1..5),
                                  noise in proptest::collection::vec(any::<u8>().prop_filter("no start", |b| *b != b':'), 0..40),
                                  cuts in proptest::collection::vec(any::<usize>(), 0..8)) {
        let line: Vec<u8> = requests.iter().flat_map(|r| [noise.clone(), ascii::frame(r.address, &r.pdu)].concat()).collect();
        let mut assembler = ascii::Assembler::default();
        let got: Vec<Request> = chunks(&line, &cuts).iter().flat_map(|c| assembler.push(c)).collect();
        prop_assert_eq!(got, requests);
        prop_assert_eq!(assembler.dropped, 0);
    }

    /// Any framing, any bytes, any chunks: every frame is at most `max_data` bytes, the
    /// queue holds at most `max_frames`, the bytes kept stay bounded, and a frame that
    /// follows (after its end bytes) is read whole.
    #[test]
    fn freeport_garbage_stays_bounded(start in proptest::option::of(any::<u8>()),
                                      end in proptest::collection::vec(any::<u8>(), 0..3),
                                      max_data in 1usize..300,
                                      bytes in proptest::collection::vec(any::<u8>(), 0..1500),
                                      cuts in proptest::collection::vec(any::<usize>(), 0..8)) {
        let framing = Framing { start, end: end.clone() };
        let mut deframer = Deframer::new(framing.clone(), max_data, 4);
        for chunk in chunks(&bytes, &cuts) {
            deframer.receive(&chunk);
        }
        let mut popped = 0;
        while let Some(received) = deframer.pop() {
            if let Received::Frame(data) = received {
                prop_assert!(data.len() <= max_data, "{} > {max_data}", data.len());
                popped += 1;
            }
        }
        prop_assert!(popped <= 4);
        // The line goes on: the end bytes close what it held, and the next frame is read
        // (unless the start byte is an end byte too: a stray one then puts every frame
        // after it out of step, on any line; nor when the end repeats its byte, "++": a
        // held "+" and the first of the closing two are an end, and the second joins the
        // next frame, on any line).
        let payload: Vec<u8> = (0..max_data.min(20)).map(|i| b'a' + (i % 26) as u8)
            .filter(|b| Some(*b) != start && !end.contains(b)).collect();
        let overlapping = end.len() == 2 && end[0] == end[1];
        prop_assume!(!payload.is_empty() && !start.is_some_and(|s| end.contains(&s)) && !overlapping);
        deframer.receive(&[&end[..], &framing.frame(&payload)].concat());
        let last = std::iter::from_fn(|| deframer.pop()).filter(|r| !matches!(r, Received::Overrun(_))).last();
        prop_assert_eq!(last, Some(Received::Frame(payload)));
    }

    /// Frames of payloads without the start or end bytes are read back as sent, in any
    /// chunks; a payload over `max_data` is `TooLong` and the frames after it still arrive.
    #[test]
    fn freeport_frames_round_trip(start in proptest::option::of(any::<u8>()),
                                  end in proptest::collection::vec(any::<u8>(), 1..3),
                                  payloads in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..80), 1..6),
                                  cuts in proptest::collection::vec(any::<usize>(), 0..8)) {
        let clean = |p: &Vec<u8>| p.iter().copied().filter(|b| Some(*b) != start && !end.contains(b)).collect::<Vec<u8>>();
        let payloads: Vec<Vec<u8>> = payloads.iter().map(clean).collect();
        let framing = Framing { start, end: end.clone() };
        let max_data = 40;
        let mut deframer = Deframer::new(framing.clone(), max_data, 8);
        let line: Vec<u8> = payloads.iter().flat_map(|p| framing.frame(p)).collect();
        for chunk in chunks(&line, &cuts) {
            deframer.receive(&chunk);
        }
        let expected: Vec<Received> = payloads.iter()
            .map(|p| if p.len() > max_data { Received::TooLong } else { Received::Frame(p.clone()) })
            .collect();
        let got: Vec<Received> = std::iter::from_fn(|| deframer.pop()).collect();
        prop_assert_eq!(got, expected);
    }
}
