//! The segment on a wire: how long a master waits for its cyclic frame through the
//! simulated drives, beside a bare raw-socket ping-pong over the same veth pair in the same
//! run, and what the segment costs per drive per frame.
//!
//! `cargo bench --bench wire` (as root: it makes a network namespace and a veth pair, and
//! removes them). The master is a raw socket on the outer end; on the inner end, inside the
//! namespace, a thread answers either with `subdevice::serve` over a segment of D1 drives
//! brought to Op by the byte-literal master of subdevice's tests (what `luamotion
//! subdevices` runs), or by sending each frame back untouched (the floor). The cyclic frame
//! is the one SOEM sends in Op: an LRW over the whole process image (6 bytes out, 10 in per
//! drive) and an FRMW of the DC system time (0x0910). The master runs on CPU 0, the answering
//! thread on CPU 1, and both sizes of frame are played on both answerers, alternately.
//!
//! The cost per drive is measured twice: the answering thread's CPU time per frame (the
//! socket's system calls included) less the floor's, and `Segment::process` alone, in a
//! loop without a wire.

#[path = "../tests/common/mod.rs"]
mod common;
#[path = "../subdevice/tests/bench/mod.rs"]
mod master;

use std::fs::File;
use std::os::fd::AsRawFd;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use hdrhistogram::Histogram;
use master::{Bench, FRMW, LRW, datagram, frame, station};
use rt_core::realtime::{confine_current_thread, thread_cpu_ns};
use subdevice::socket::FRAME_BUFFER_LEN;
use subdevice::{RawSocket, Segment};

const DRIVES: [usize; 4] = [1, 4, 16, 64];
const ROUNDS: usize = 2;
const WARM_UP: usize = 2_000;
const FRAMES: usize = 40_000;
const PROCESS_LOOPS: usize = 20_000;
/// How long the master waits for one frame back before it calls the run broken.
const FRAME_DEADLINE: Duration = Duration::from_secs(2);

/// What answers the master on the inner end.
enum Answerer {
    /// Each frame sent back as it came: the wire's and the sockets' floor.
    Echo,
    /// The segment, through `subdevice::serve`.
    Segment(Box<Segment>),
}

/// One run of the master against one answerer.
struct Run {
    round_trip: Histogram<u64>,
    /// The answering thread's CPU time per frame answered, ns.
    cpu_per_frame: f64,
}

fn main() {
    let wire = common::wire::Wire::new().expect("the bench makes a veth pair: it needs root or CAP_NET_ADMIN");
    let mut table = Vec::new();
    for &drives in &DRIVES {
        let mut echo: Option<Run> = None;
        let mut segment: Option<Run> = None;
        for _ in 0..ROUNDS {
            merge(&mut echo, play(&wire, drives, Answerer::Echo));
            merge(&mut segment, play(&wire, drives, Answerer::Segment(Box::new(segment_in_op(drives)))));
        }
        table.push((drives, echo.unwrap(), segment.unwrap(), process_alone(drives)));
    }
    println!(
        "| drives | frame bytes | round trip p50 / p99 / p99.9 / max, us (floor: echo) | answering thread CPU per frame, us (floor) | per drive, ns: CPU less the floor / Segment::process alone |"
    );
    println!("|---|---|---|---|---|");
    for (drives, echo, segment, alone) in table {
        let us = |h: &Histogram<u64>, q: f64| h.value_at_quantile(q) as f64 / 1000.0;
        let quantiles = |h: &Histogram<u64>| {
            format!("{:.1} / {:.1} / {:.1} / {:.0}", us(h, 0.5), us(h, 0.99), us(h, 0.999), h.max() as f64 / 1000.0)
        };
        println!(
            "| {drives} | {} | {} ({}) | {:.2} ({:.2}) | {:.0} / {:.0} |",
            cyclic_frame(drives).len(),
            quantiles(&segment.round_trip),
            quantiles(&echo.round_trip),
            segment.cpu_per_frame / 1000.0,
            echo.cpu_per_frame / 1000.0,
            (segment.cpu_per_frame - echo.cpu_per_frame) / drives as f64,
            alone / drives as f64,
        );
    }
}

/// The frame a master sends each cycle in Op (SOEM's `send_processdata` with DC).
fn cyclic_frame(drives: usize) -> Vec<u8> {
    frame(&[datagram(LRW, 0, 0, vec![0; 16 * drives]), datagram(FRMW, station(0), 0x0910, vec![0; 8])])
}

/// `drives` D1 drives in Op, their FMMUs on one image.
fn segment_in_op(drives: usize) -> Segment {
    let mut bench = Bench::drives(drives);
    bench.bring_up();
    bench.segment
}

/// ns per frame of `Segment::process` alone, the cyclic frame of a segment in Op.
fn process_alone(drives: usize) -> f64 {
    let mut segment = segment_in_op(drives);
    let request = cyclic_frame(drives);
    let mut bytes = request.clone();
    let mut now = 1_000_000_000;
    let start = Instant::now();
    for _ in 0..PROCESS_LOOPS {
        bytes.copy_from_slice(&request);
        now += 1_000_000;
        segment.process(&mut bytes, now).expect("a well-formed frame");
    }
    start.elapsed().as_nanos() as f64 / PROCESS_LOOPS as f64
}

fn merge(into: &mut Option<Run>, run: Run) {
    match into {
        None => *into = Some(run),
        Some(sum) => {
            sum.round_trip.add(&run.round_trip).unwrap();
            sum.cpu_per_frame = (sum.cpu_per_frame + run.cpu_per_frame) / 2.0;
        }
    }
}

/// `WARM_UP + FRAMES` cyclic frames from the outer end, each waited for, against `answerer`
/// on the inner end.
fn play(wire: &common::wire::Wire, drives: usize, answerer: Answerer) -> Run {
    let expected_wkc = match answerer {
        Answerer::Echo => 0,
        // Each drive's outputs written and inputs read: LRW counts 3 for a slave with both.
        Answerer::Segment(_) => 3 * drives as u16,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let answering = answer(wire, answerer, Arc::clone(&stop), ready_tx);
    ready_rx.recv_timeout(Duration::from_secs(10)).expect("the answering thread bound its socket");
    assert!(confine_current_thread(&[0]), "pinned to CPU 0");
    let socket = RawSocket::bind(&wire.outside).expect("a raw socket on the outer end");
    let request = cyclic_frame(drives);
    let mut reply = [0u8; FRAME_BUFFER_LEN];
    let mut round_trip = Histogram::<u64>::new(3).unwrap();
    for i in 0..WARM_UP + FRAMES {
        let sent = Instant::now();
        socket.send(&request).expect("send");
        let n = loop {
            match socket.receive(&mut reply, FRAME_DEADLINE).expect("receive") {
                Some(n) => break n,
                None if sent.elapsed() > FRAME_DEADLINE => {
                    panic!("frame {i} of {drives} drives: no answer within {FRAME_DEADLINE:?}")
                }
                None => {}
            }
        };
        let elapsed = sent.elapsed();
        let answers = master::answers(&reply[..n]);
        assert_eq!(answers[0].wkc, expected_wkc, "the LRW's working counter, frame {i}");
        if i >= WARM_UP {
            round_trip.record(elapsed.as_nanos() as u64).unwrap();
        }
    }
    stop.store(true, Ordering::Relaxed);
    let (answered, cpu_ns) = answering.join().expect("the answering thread");
    assert_eq!(answered, (WARM_UP + FRAMES) as u64, "every frame answered once");
    Run { round_trip, cpu_per_frame: cpu_ns as f64 / answered as f64 }
}

/// The answering thread: in the wire's namespace, on CPU 1, a raw socket on the inner end;
/// it returns the frames it answered and its CPU time from the bind on.
fn answer(
    wire: &common::wire::Wire,
    answerer: Answerer,
    stop: Arc<AtomicBool>,
    ready: std::sync::mpsc::Sender<()>,
) -> JoinHandle<(u64, u64)> {
    let namespace = File::open(format!("/run/netns/{}", wire.namespace)).expect("the namespace's file");
    let interface = wire.inside.clone();
    std::thread::spawn(move || {
        // SAFETY: a descriptor of a network namespace, entered by this thread only.
        let entered = unsafe { libc::setns(namespace.as_raw_fd(), libc::CLONE_NEWNET) };
        assert_eq!(entered, 0, "setns: {}", std::io::Error::last_os_error());
        assert!(confine_current_thread(&[1]), "pinned to CPU 1");
        let socket = RawSocket::bind(&interface).expect("a raw socket on the inner end");
        let start = thread_cpu_ns();
        ready.send(()).unwrap();
        let answered = match answerer {
            Answerer::Echo => echo(&socket, &stop),
            Answerer::Segment(mut segment) => subdevice::serve(&mut segment, &socket, &stop).expect("serve").answered,
        };
        (answered, thread_cpu_ns() - start)
    })
}

/// Every frame back as it came, until `stop`.
fn echo(socket: &RawSocket, stop: &AtomicBool) -> u64 {
    let mut buffer = [0u8; FRAME_BUFFER_LEN];
    let mut answered = 0;
    while !stop.load(Ordering::Relaxed) {
        if let Some(n) = socket.receive(&mut buffer, Duration::from_millis(100)).expect("receive") {
            socket.send(&buffer[..n]).expect("send");
            answered += 1;
        }
    }
    answered
}
