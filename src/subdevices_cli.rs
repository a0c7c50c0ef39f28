//! `luamotion subdevices`: the machine file's drives and I/O slaves as an EtherCAT segment
//! on a network interface, for a master on the other end of the wire (SOEM, TwinCAT, a
//! second controller). The devices are the ones `run` simulates (`devices`), each behind an
//! ESC (`subdevice`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result};
use config::{MachineConfig, SlaveDevice};
use devices::ecat::Network;
use subdevice::{Esc, RawSocket, Segment};

/// How far apart the ESCs' local clocks start (ns): each ESC powered up at its own
/// moment, so a master meets clocks it has to align (an odd step, not a round one).
const BOOT_SPREAD_NS: u64 = 1_000_000_007;

#[derive(clap::Args)]
pub struct SubdevicesArgs {
    /// The network interface (it needs CAP_NET_RAW), e.g. eth1 or one end of a veth pair.
    #[arg(long)]
    interface: String,
    /// Machine file (TOML); without it, the built-in machine: 4 axes on D1 drives.
    #[arg(long)]
    config: Option<PathBuf>,
    /// SCHED_FIFO priority of the thread that answers frames, as hardware answers them
    /// whatever else runs (0: a plain thread). Below the controller's RT thread (80).
    #[arg(long, default_value_t = 70, value_parser = clap::value_parser!(u8).range(0..=99))]
    priority: u8,
}

/// Serves the segment until SIGINT or SIGTERM.
pub fn subdevices(args: SubdevicesArgs) -> Result<ExitCode> {
    let machine = match &args.config {
        Some(path) => MachineConfig::load(path)?,
        None => MachineConfig::default(),
    };
    let names = machine.axes.iter().map(|axis| format!("HIWIN {:?} CoE drive", axis.drive)).chain(
        machine.slaves.iter().map(|slave| match slave.device {
            SlaveDevice::DigitalIo => "digital I/O terminal".to_string(),
            SlaveDevice::AnalogIo => "analog I/O terminal".to_string(),
        }),
    );
    let escs: Vec<Esc> = Network::for_machine(&machine)
        .into_slaves()
        .into_iter()
        .zip(names)
        .enumerate()
        .map(|(i, (slave, name))| Esc::new(slave, &name, BOOT_SPREAD_NS * (i as u64 + 1)))
        .collect();
    let count = escs.len();
    let mut segment = Segment::new(escs);
    let socket = RawSocket::bind(&args.interface)?;
    let stop = Arc::new(AtomicBool::new(false));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(signal, Arc::clone(&stop)).context("signal handler")?;
    }
    tracing::info!("{count} subdevices on {}", args.interface);
    // A segment is machinery a master drives: a log reader that goes away must not stop it.
    crate::stdout::sayln!("serving {count} subdevices on {}", args.interface);
    subdevice::realtime::fifo_or_plain(args.priority, "the segment");
    let served = subdevice::serve(&mut segment, &socket, &stop).context("the raw socket")?;
    tracing::info!(
        "{} frames answered, {} dropped, {} not sent (link down)",
        served.answered,
        served.dropped,
        served.unsent
    );
    Ok(ExitCode::SUCCESS)
}
