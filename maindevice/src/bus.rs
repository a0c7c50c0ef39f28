//! The MainDevice's threads: "ecat-txrx" moves ethercrab's frames through the raw socket,
//! "ecat-master" runs the start-up and then one process-data frame each time the cycle
//! rings it. The cycle holds a `WireBus` and only hands images over.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use ethercrab::subdevice_group::DcConfiguration;
use ethercrab::{DcSync, MainDevice, MainDeviceConfig, PduStorage, SubDeviceGroup, Timeouts, std::ethercat_now};

use crate::error::WireError;
use crate::handoff::{self, CycleSide, Exchange, MasterSide};
use crate::plan::{Identity, Plan};

/// Slaves ethercrab's group can hold.
const MAX_SUBDEVICES: usize = 128;
/// Bytes of ethercrab's process data image.
const MAX_PDI: usize = 4096;
/// Frames in flight, and the room of each.
const MAX_FRAMES: usize = 16;
const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
/// How long the master waits for the first cycle's ring before it looks at its stop flag.
const IDLE: Duration = Duration::from_millis(100);
/// How long the segment may take from SafeOp to Op with process data running.
const OP_DEADLINE: Duration = Duration::from_secs(10);

type Storage = PduStorage<MAX_FRAMES, MAX_PDU_DATA>;

/// The segment on a wire, in Op, for the cycle.
pub struct WireBus {
    cycle: CycleSide,
    stop: Arc<AtomicBool>,
    master: Option<JoinHandle<()>>,
}

impl WireBus {
    /// Scans the segment on `interface`, checks it against `plan`, downloads each slave's
    /// start-up list in PreOp, configures SYNC0 at `cycle_ns` and brings every slave to Op.
    /// Returns once the segment is in Op, or with what stopped it.
    pub fn start(interface: &str, plan: Plan, cycle_ns: u64) -> Result<WireBus, WireError> {
        let stop = Arc::new(AtomicBool::new(false));
        let (started_tx, started_rx) = mpsc::channel();
        let (interface, thread_stop) = (interface.to_string(), Arc::clone(&stop));
        let master = std::thread::Builder::new()
            .name("ecat-master".into())
            .stack_size(8 << 20)
            .spawn(move || {
                let (cycle, master) =
                    handoff::handoff(plan.outputs_len, plan.inputs_len, plan.working_counter(), std::thread::current());
                // The TX/RX thread drives async-io's reactor; this one parks between frames.
                futures_lite::future::block_on(run(
                    &interface,
                    &plan,
                    cycle_ns,
                    cycle,
                    master,
                    &thread_stop,
                    started_tx,
                ));
            })
            .map_err(|error| WireError::Thread { name: "ecat-master", error })?;
        match started_rx.recv() {
            Ok(Ok(cycle)) => Ok(WireBus { cycle, stop, master: Some(master) }),
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

impl Drop for WireBus {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(master) = self.master.take() {
            master.thread().unpark();
            let _ = master.join();
        }
    }
}

/// The master thread: start-up, then frames on the cycle's rings until `stop`.
async fn run(
    interface: &str,
    plan: &Plan,
    cycle_ns: u64,
    cycle: CycleSide,
    mut side: MasterSide,
    stop: &AtomicBool,
    started: mpsc::Sender<Result<CycleSide, WireError>>,
) {
    // One storage per bus, for the life of the process: ethercrab splits it once.
    let storage: &'static Storage = Box::leak(Box::new(Storage::new()));
    let Ok((tx, rx, pdu_loop)) = storage.try_split() else {
        let _ = started.send(Err(WireError::ThreadEnded));
        return;
    };
    let cycle_time = Duration::from_nanos(cycle_ns);
    let timeouts = Timeouts {
        // A frame lost in the cycle costs the master this long; the cycle does not wait.
        pdu: Duration::from_millis(50),
        state_transition: Duration::from_secs(5),
        mailbox_response: Duration::from_secs(1),
        ..Timeouts::default()
    };
    let maindevice = MainDevice::new(pdu_loop, timeouts, MainDeviceConfig::default());
    let task = match ethercrab::std::tx_rx_task(interface, tx, rx) {
        Ok(task) => task,
        Err(error) => {
            let _ = started.send(Err(WireError::Interface { interface: interface.to_string(), error }));
            return;
        }
    };
    // This thread drives async-io's reactor (the socket and ethercrab's timeouts).
    let txrx = std::thread::Builder::new().name("ecat-txrx".into()).spawn(move || {
        if let Err(error) = async_io::block_on(task) {
            tracing::error!("EtherCAT TX/RX stopped: {error}");
        }
    });
    if let Err(error) = txrx {
        let _ = started.send(Err(WireError::Thread { name: "ecat-txrx", error }));
        return;
    }
    let group = match start_up(&maindevice, plan, cycle_time).await {
        Ok(group) => group,
        Err(error) => {
            let _ = started.send(Err(error));
            // SAFETY: the group is gone; nothing else uses the storage.
            let _ = unsafe { maindevice.release_all() };
            return;
        }
    };
    let _ = started.send(Ok(cycle));
    let mut sequence = 0;
    while !stop.load(Ordering::Relaxed) {
        std::thread::park_timeout(IDLE);
        if !side.outputs.update() {
            continue;
        }
        let outputs = side.outputs.output_buffer_mut();
        for (slave, subdevice) in plan.slaves.iter().zip(group.iter(&maindevice)) {
            let mut io = subdevice.io_raw_mut();
            let n = io.outputs().len().min(slave.outputs.len());
            io.outputs()[..n].copy_from_slice(&outputs[slave.outputs.start..slave.outputs.start + n]);
        }
        let working_counter = group.tx_rx_dc(&maindevice).await.ok().map(|response| response.working_counter);
        sequence += 1;
        let returned = side.returned.input_buffer_mut();
        returned.sequence = sequence;
        returned.working_counter = working_counter;
        for (slave, subdevice) in plan.slaves.iter().zip(group.iter(&maindevice)) {
            let io = subdevice.io_raw();
            let n = io.inputs().len().min(slave.inputs.len());
            returned.inputs[slave.inputs.start..slave.inputs.start + n].copy_from_slice(&io.inputs()[..n]);
        }
        side.returned.publish();
    }
    drop(group);
    // SAFETY: the group is gone; this wakes the TX/RX thread to end it.
    let _ = unsafe { maindevice.release_all() };
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
    let mut group =
        maindevice.init_single_group::<MAX_SUBDEVICES, MAX_PDI>(ethercat_now).await.map_err(master("scan"))?;
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
    // SYNC0 slaves reach Op only with process data running (the SM watchdog).
    let deadline = Instant::now() + OP_DEADLINE;
    loop {
        let response = group.tx_rx_dc(maindevice).await.map_err(master("process data to Op"))?;
        if response.all_op() {
            return Ok(group);
        }
        if Instant::now() > deadline {
            return Err(WireError::NotOp { waited: OP_DEADLINE });
        }
        async_io::Timer::after(cycle_time).await;
    }
}
