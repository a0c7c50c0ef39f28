//! The MainDevice's threads: "ecat-txrx" moves ethercrab's frames through the raw socket
//! (`txrx.rs`),
//! "ecat-master" runs the start-up and then one process-data frame each time the cycle
//! rings it, and "ecat-mailbox" the SDO transfers the cycle queues. The cycle holds a
//! `WireBus` and only hands images and requests over.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU64, Ordering};
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use ethercrab::subdevice_group::DcConfiguration;
use ethercrab::{
    DcSync, MainDevice, MainDeviceConfig, PduStorage, RegisterAddress, RetryBehaviour, SubDeviceGroup, SubDeviceState,
    Timeouts, std::ethercat_now,
};

use devices::cia402::State;
use devices::ecat::{AlState, Exchange, Remote, SdoAnswer, SdoError, SdoRequest};
use futures_lite::future::block_on;

use crate::error::WireError;
use crate::handoff::{self, CycleSide, MasterSide};
use crate::mailbox::{self, CycleMailbox, WireMailbox};
use crate::plan::{Identity, Plan};
use crate::txrx::TxRx;

/// Slaves ethercrab's group can hold.
const MAX_SUBDEVICES: usize = 128;
/// Bytes of ethercrab's process data image.
const MAX_PDI: usize = 4096;
/// Frames in flight, and the room of each.
const MAX_FRAMES: usize = 16;
/// A full Ethernet frame (1514 bytes without its checksum, ethercrab's 28 of it headers).
const MAX_PDU_DATA: usize = PduStorage::element_size(1486);
/// The process image must go in one LRW beside the DC time's FRMW (10 + 8 + 2 bytes): the
/// working counter the cycle checks is that of one datagram over every slave.
pub const MAX_IMAGE: usize = 1486 - 20;
/// How long the cycle may go without a complete frame before the segment counts as lost:
/// longer than a lost frame's resends take, well inside a drive's 100 ms process data
/// watchdog (ETG.1000.4 6.3).
pub const LOST_AFTER: Duration = Duration::from_millis(20);

/// The shortest wait for a frame before it is sent again, and how often it is.
const MIN_PDU_TIMEOUT: Duration = Duration::from_millis(2);
const PDU_RETRIES: usize = 3;
/// AL control: Op with the error acknowledged (ETG.1000.6 table 9).
const OP_ACKNOWLEDGED: u16 = 0x08 | 0x10;
/// How often the master asks slaves that fell out of Op to come back.
const RECOVERY_INTERVAL: Duration = Duration::from_millis(100);
/// Scans before a segment that does not answer stops the start.
const SCANS: u32 = 3;
/// Between scans: time for a segment switched on with the controller to boot.
const SCAN_PAUSE: Duration = Duration::from_millis(500);
/// How long the segment may take from SafeOp to Op with process data running.
const OP_DEADLINE: Duration = Duration::from_secs(10);

type Storage = PduStorage<MAX_FRAMES, MAX_PDU_DATA>;

/// The segment on a wire, in Op, for the cycle.
pub struct WireBus {
    cycle: CycleSide,
    mailbox: CycleMailbox,
    unmatched: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    master: Option<JoinHandle<()>>,
}

impl WireBus {
    /// `LOST_AFTER` in cycles of `cycle_ns`.
    pub fn lost_after_cycles(cycle_ns: u64) -> u32 {
        (LOST_AFTER.as_nanos() as u64).div_ceil(cycle_ns.max(1)) as u32
    }

    /// Scans the segment on `interface`, checks it against `plan`, downloads each slave's
    /// start-up list in PreOp, configures SYNC0 at `cycle_ns` and brings every slave to Op.
    /// The threads that carry frames ("ecat-master", "ecat-txrx") run at SCHED_FIFO
    /// `priority` (0: plain threads). Returns once the segment is in Op, or with what
    /// stopped it.
    pub fn start(interface: &str, plan: Plan, cycle_ns: u64, priority: u8) -> Result<WireBus, WireError> {
        let image = plan.inputs_len + plan.outputs_len;
        if image > MAX_IMAGE {
            return Err(WireError::ImageTooLarge { bytes: image, max: MAX_IMAGE });
        }
        let stop = Arc::new(AtomicBool::new(false));
        let (started_tx, started_rx) = mpsc::channel();
        let (interface, thread_stop) = (interface.to_string(), Arc::clone(&stop));
        let (cycle_mailbox, wire_mailbox) = mailbox::queues();
        let unmatched = Arc::new(AtomicU64::new(0));
        let counted = Arc::clone(&unmatched);
        let master = std::thread::Builder::new()
            .name("ecat-master".into())
            .stack_size(8 << 20)
            .spawn(move || {
                subdevice::realtime::fifo_or_plain(priority, "ecat-master");
                let (cycle, master) =
                    handoff::handoff(plan.outputs_len, plan.inputs_len, plan.working_counter(), std::thread::current());
                let lowest = AtomicU8::new(AlState::Op.code());
                let wire = Wire {
                    interface: &interface,
                    plan: &plan,
                    cycle_ns,
                    priority,
                    stop: &thread_stop,
                    lowest,
                    unmatched,
                };
                wire.run(cycle, master, wire_mailbox, started_tx);
            })
            .map_err(|error| WireError::Thread { name: "ecat-master", error })?;
        match started_rx.recv() {
            Ok(Ok(cycle)) => {
                Ok(WireBus { cycle, mailbox: cycle_mailbox, unmatched: counted, stop, master: Some(master) })
            }
            Ok(Err(error)) => {
                let _ = master.join();
                Err(error)
            }
            Err(_) => {
                let _ = master.join();
                Err(WireError::ThreadEnded)
            }
        }
    }

    /// One cycle: the inputs of the last frame into `inputs`, `outputs` handed over for the
    /// next. Never waits.
    pub fn exchange(&mut self, outputs: &[u8], inputs: &mut [u8]) -> Exchange {
        self.cycle.exchange(outputs, inputs)
    }
}

impl Remote for WireBus {
    fn exchange(&mut self, outputs: &[u8], inputs: &mut [u8]) -> Exchange {
        WireBus::exchange(self, outputs, inputs)
    }

    fn request(&mut self, request: SdoRequest) -> Result<(), SdoError> {
        self.mailbox.request(request)
    }

    fn answer(&mut self) -> Option<SdoAnswer> {
        self.mailbox.answer()
    }

    fn state(&self) -> AlState {
        self.cycle.state()
    }

    fn unmatched(&self) -> u64 {
        self.unmatched.load(Ordering::Relaxed)
    }
}

impl Drop for WireBus {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(master) = self.master.take() {
            master.thread().unpark();
            let _ = master.join();
        }
    }
}

/// What the master thread works with.
struct Wire<'a> {
    interface: &'a str,
    plan: &'a Plan,
    cycle_ns: u64,
    /// SCHED_FIFO priority of the threads that carry frames.
    priority: u8,
    stop: &'a AtomicBool,
    /// The lowest AL state of the last frame back, as its code (ETG.1000.6 table 9).
    lowest: AtomicU8,
    /// Frames back that matched nothing in flight (`TxRx`).
    unmatched: Arc<AtomicU64>,
}

impl Wire<'_> {
    /// The master thread: start-up, then frames on the cycle's rings and the mailbox's
    /// transfers beside them until `stop`.
    fn run(
        &self,
        cycle: CycleSide,
        side: MasterSide,
        mailbox: WireMailbox,
        started: mpsc::Sender<Result<CycleSide, WireError>>,
    ) {
        // One storage per bus, for the life of the process: ethercrab splits it once.
        let storage: &'static Storage = Box::leak(Box::new(Storage::new()));
        let Ok((tx, rx, pdu_loop)) = storage.try_split() else {
            let _ = started.send(Err(WireError::ThreadEnded));
            return;
        };
        let timeouts = Timeouts {
            // A frame lost costs the master this long before it sends it again, and the
            // cycle that many frames; the cycle itself does not wait.
            pdu: Duration::from_nanos(self.cycle_ns * 3).max(MIN_PDU_TIMEOUT),
            state_transition: Duration::from_secs(5),
            mailbox_response: Duration::from_secs(1),
            ..Timeouts::default()
        };
        let config =
            MainDeviceConfig { retry_behaviour: RetryBehaviour::Count(PDU_RETRIES), ..MainDeviceConfig::default() };
        let maindevice = MainDevice::new(pdu_loop, timeouts, config);
        let socket = match subdevice::RawSocket::bind(self.interface) {
            Ok(socket) => socket,
            Err(error) => {
                let _ = started.send(Err(WireError::Interface { interface: self.interface.to_string(), error }));
                return;
            }
        };
        let task = match TxRx::new(socket, tx, rx, Arc::clone(&self.unmatched)) {
            Ok(task) => task,
            Err(error) => {
                let _ = started.send(Err(WireError::Thread { name: "ecat-txrx", error }));
                return;
            }
        };
        // This thread drives async-io's reactor (the socket and ethercrab's timeouts).
        let priority = self.priority;
        let txrx = std::thread::Builder::new().name("ecat-txrx".into()).spawn(move || {
            subdevice::realtime::fifo_or_plain(priority, "ecat-txrx");
            async_io::block_on(task)
        });
        if let Err(error) = txrx {
            let _ = started.send(Err(WireError::Thread { name: "ecat-txrx", error }));
            return;
        }
        match block_on(start_up(&maindevice, self.plan, Duration::from_nanos(self.cycle_ns))) {
            Ok(group) => {
                let _ = started.send(Ok(cycle));
                std::thread::scope(|scope| {
                    let transfers = std::thread::Builder::new()
                        .name("ecat-mailbox".into())
                        .spawn_scoped(scope, || self.serve_mailbox(&maindevice, &group, mailbox));
                    if let Err(error) = transfers {
                        tracing::error!(
                            "the EtherCAT mailbox thread could not start: {error}; SDOs will not be answered"
                        );
                    }
                    self.exchange_process_data(&maindevice, &group, side);
                });
                // A master that ends takes its slaves out of Op, so that their process
                // data watchdogs do not fault the drives (a crash leaves them to it).
                let down = block_on(async {
                    let group = group.into_safe_op(&maindevice).await?;
                    group.into_pre_op(&maindevice).await?.into_init(&maindevice).await
                });
                if let Err(error) = down {
                    tracing::warn!("EtherCAT: the slaves did not go back to Init: {error}");
                }
            }
            Err(error) => {
                let _ = started.send(Err(error));
            }
        }
        // SAFETY: the group is gone; this wakes the TX/RX thread to end it.
        let _ = unsafe { maindevice.release_all() };
    }

    /// One frame each time the cycle rings with new outputs; the inputs it brought back
    /// published with its working counter.
    fn exchange_process_data(&self, maindevice: &MainDevice<'_>, group: &OpGroup, mut side: MasterSide) {
        let mut sequence = 0;
        // Without a ring in two cycles the last outputs go again: the slaves' process data
        // watchdogs must not run out while the cycle is not running (yet, or any more).
        let keep_alive = Duration::from_nanos(2 * self.cycle_ns);
        let (lost_after, mut missing_in_a_row) = (WireBus::lost_after_cycles(self.cycle_ns), 0);
        while !self.stop.load(Ordering::Relaxed) {
            std::thread::park_timeout(keep_alive);
            side.outputs.update();
            let outputs = side.outputs.output_buffer_mut();
            for (slave, subdevice) in self.plan.slaves.iter().zip(group.iter(maindevice)) {
                let mut io = subdevice.io_raw_mut();
                let n = io.outputs().len().min(slave.outputs.len());
                io.outputs()[..n].copy_from_slice(&outputs[slave.outputs.start..slave.outputs.start + n]);
            }
            let response = block_on(group.tx_rx_dc(maindevice)).ok();
            let lowest = response.as_ref().and_then(|r| r.subdevice_states.iter().map(|&s| al_state(s)).min());
            sequence += 1;
            let returned = side.returned.input_buffer_mut();
            returned.sequence = sequence;
            returned.working_counter = response.as_ref().map(|r| r.working_counter);
            match lowest {
                Some(lowest) => {
                    returned.lowest = lowest;
                    self.lowest.store(lowest.code(), Ordering::Relaxed);
                    missing_in_a_row = 0;
                }
                // After as long as the cycle counts the segment lost, the slaves' states are
                // not known any more: the mailbox thread looks at them until they answer.
                None => {
                    missing_in_a_row += 1;
                    if missing_in_a_row >= lost_after {
                        self.lowest.store(AlState::Init.code(), Ordering::Relaxed);
                    }
                }
            }
            for (slave, subdevice) in self.plan.slaves.iter().zip(group.iter(maindevice)) {
                let io = subdevice.io_raw();
                let n = io.inputs().len().min(slave.inputs.len());
                returned.inputs[slave.inputs.start..slave.inputs.start + n].copy_from_slice(&io.inputs()[..n]);
            }
            side.returned.publish();
        }
    }

    /// The cycle's SDO transfers, one after the other, until `stop`; and slaves that fell
    /// out of Op (the cable was out, their watchdog ran out) asked back, error acknowledged,
    /// as a master restores its slaves' states.
    fn serve_mailbox(&self, maindevice: &MainDevice<'_>, group: &OpGroup, mailbox: WireMailbox) {
        let mut last_recovery = Instant::now();
        while !self.stop.load(Ordering::Relaxed) {
            if self.lowest.load(Ordering::Relaxed) != AlState::Op.code() && last_recovery.elapsed() > RECOVERY_INTERVAL
            {
                last_recovery = Instant::now();
                self.recover(maindevice, group);
            }
            let Ok(request) = mailbox.requests.recv_timeout(RECOVERY_INTERVAL) else { continue };
            let result = match group.subdevice(maindevice, usize::from(request.slave)) {
                Ok(subdevice) => block_on(mailbox::transfer(&subdevice, request)),
                Err(_) => Err(SdoError::NoSlave(usize::from(request.slave))),
            };
            if mailbox.answers.send(SdoAnswer { request, result }).is_err() {
                return;
            }
        }
    }
}

impl Wire<'_> {
    /// Each slave not in Op asked for Op with its error acknowledged.
    fn recover(&self, maindevice: &MainDevice<'_>, group: &OpGroup) {
        for subdevice in group.iter(maindevice) {
            // ethercrab gives a status with the error flag as an error holding its code.
            let status = block_on(subdevice.status());
            if !matches!(status, Ok((SubDeviceState::Op, _))) {
                let address = subdevice.configured_address();
                tracing::warn!("EtherCAT slave {address:#06x}: {status:?}; asked back to Op");
                let _ = block_on(subdevice.register_write(RegisterAddress::AlControl, OP_ACKNOWLEDGED));
            }
        }
    }
}

/// ethercrab's AL state as the devices' one; a state no slave should be in as Init.
fn al_state(state: SubDeviceState) -> AlState {
    match state {
        SubDeviceState::Op => AlState::Op,
        SubDeviceState::SafeOp => AlState::SafeOp,
        SubDeviceState::PreOp => AlState::PreOp,
        _ => AlState::Init,
    }
}

type OpGroup = SubDeviceGroup<
    MAX_SUBDEVICES,
    MAX_PDI,
    ethercrab::DefaultLock,
    ethercrab::subdevice_group::Op,
    ethercrab::subdevice_group::HasDc,
>;

/// Scan, checks, start-up lists, DC, SafeOp, Op.
async fn start_up<'sto>(
    maindevice: &'sto MainDevice<'sto>,
    plan: &Plan,
    cycle_time: Duration,
) -> Result<OpGroup, WireError> {
    let master = |step| move |error| WireError::Master { step, error };
    // A scan is a few dozen frames that each must come back; one lost past its resends
    // (a busy machine, a cable plugged in just then) costs a scan again, not the start.
    let mut scans = 1;
    let mut group = loop {
        match maindevice.init_single_group::<MAX_SUBDEVICES, MAX_PDI>(ethercat_now).await {
            Err(error @ ethercrab::error::Error::Timeout(_)) if scans < SCANS => {
                tracing::warn!("EtherCAT scan {scans} of {SCANS}: {error}; scanning again in {SCAN_PAUSE:?}");
                scans += 1;
                async_io::Timer::after(SCAN_PAUSE).await;
            }
            scanned => break scanned.map_err(master("scan"))?,
        }
    };
    if group.len() != plan.slaves.len() {
        return Err(WireError::SlaveCount { found: group.len(), expected: plan.slaves.len() });
    }
    for (slave, (planned, mut subdevice)) in plan.slaves.iter().zip(group.iter_mut(maindevice)).enumerate() {
        let id = subdevice.identity();
        let found = Identity { vendor: id.vendor_id, product: id.product_id, revision: id.revision };
        if found != planned.identity {
            return Err(WireError::WrongSlave {
                slave,
                name: subdevice.name().to_string(),
                found,
                expected: planned.identity,
            });
        }
        for download in &planned.startup {
            let (index, sub) = (download.index, download.sub);
            let result = match download.data[..] {
                [b] => subdevice.sdo_write(index, sub, b).await,
                [a, b] => subdevice.sdo_write(index, sub, u16::from_le_bytes([a, b])).await,
                [a, b, c, d] => subdevice.sdo_write(index, sub, u32::from_le_bytes([a, b, c, d])).await,
                _ => Err(ethercrab::error::Error::Internal),
            };
            result.map_err(|error| WireError::Sdo { slave, index, sub, error })?;
        }
        subdevice.set_dc_sync(DcSync::Sync0);
    }
    let group = group.into_pre_op_pdi(maindevice).await.map_err(master("PreOp with process data"))?;
    for (slave, (planned, subdevice)) in plan.slaves.iter().zip(group.iter(maindevice)).enumerate() {
        let io = subdevice.io_raw();
        let (outputs, inputs) = (io.outputs().len(), io.inputs().len());
        if (outputs, inputs) != (planned.outputs.len(), planned.inputs.len()) {
            return Err(WireError::Mapping {
                slave,
                what: format!("{outputs} bytes of outputs and {inputs} of inputs"),
                planned: format!("{} and {}", planned.outputs.len(), planned.inputs.len()),
            });
        }
    }
    let dc = DcConfiguration {
        start_delay: Duration::from_millis(100),
        sync0_period: cycle_time,
        sync0_shift: Duration::ZERO,
    };
    let group = group.configure_dc_sync(maindevice, dc).await.map_err(master("DC SYNC0"))?;
    let group = group.into_safe_op(maindevice).await.map_err(master("PreOp to SafeOp"))?;
    let group = group.request_into_op(maindevice).await.map_err(master("SafeOp to Op"))?;
    // SYNC0 slaves reach Op only with process data running (the SM watchdog); a CiA 402
    // drive leaves Not ready to switch on by itself once running (CoE manual 3.1,
    // transition 1), and the controller starts its programs after that.
    // A frame lost on the way is sent again in the next cycle, as in Op; only the deadline
    // ends the wait.
    let deadline = Instant::now() + OP_DEADLINE;
    loop {
        let response = match group.tx_rx_dc(maindevice).await {
            Ok(response) => response,
            Err(_) if Instant::now() <= deadline => {
                async_io::Timer::after(cycle_time).await;
                continue;
            }
            Err(error) => return Err(master("process data to Op")(error)),
        };
        let drives_ready = plan.slaves.iter().zip(group.iter(maindevice)).all(|(planned, subdevice)| {
            let statusword = planned.tx.iter().find(|e| (e.index, e.sub) == (STATUSWORD, 0));
            statusword.is_none_or(|e| {
                let io = subdevice.io_raw();
                let bytes = io.inputs().get(e.offset..e.offset + 2);
                let state = bytes.map(|b| State::from_statusword(u16::from_le_bytes([b[0], b[1]])));
                state.is_some_and(|s| s != Some(State::NotReadyToSwitchOn))
            })
        });
        if response.all_op() && drives_ready {
            return Ok(group);
        }
        if Instant::now() > deadline {
            return Err(WireError::NotOp { waited: OP_DEADLINE });
        }
        async_io::Timer::after(cycle_time).await;
    }
}

/// The CiA 402 statusword (CoE manual table 3-4), decoded with table 3-5's masks.
const STATUSWORD: u16 = 0x6041;

#[cfg(test)]
mod tests {
    use super::*;

    /// An image one LRW cannot carry is refused before any frame goes out (and without an
    /// interface: the check comes first).
    #[test]
    fn an_image_larger_than_one_frame_is_refused() {
        let plan = Plan { slaves: Vec::new(), outputs_len: 1000, inputs_len: 467 };
        match WireBus::start("no-such-interface", plan, 1_000_000, 0) {
            Err(WireError::ImageTooLarge { bytes: 1467, max: MAX_IMAGE }) => {}
            other => panic!("{:?}", other.err()),
        }
        let fits = Plan { slaves: Vec::new(), outputs_len: 1000, inputs_len: 466 };
        let error = WireBus::start("no-such-interface", fits, 1_000_000, 0).err().expect("no such interface");
        assert!(matches!(error, WireError::Interface { .. }), "{error}");
    }
}
