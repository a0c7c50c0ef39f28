//! The outside inputs of `luamotion run` on the simulation clock (`rt_core::replay`):
//! `--record FILE` writes them with their cycles, `--replay FILE` feeds them back, and
//! `--modbus-port` serves the Modbus TCP registers whose writes are such inputs.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{Context, Result, bail};
use rt_core::replay::{self, Feed, Input, Inputs, Stamped};
use rt_core::sim_clock::{Clock, Speed};

#[derive(clap::Args)]
pub struct InputArgs {
    /// With `--clock sim`: write the run's outside inputs (Modbus writes of DV, DH and
    /// FUN147 words, the bytes serial port 1 receives in FreePort, the web view's simulated
    /// inputs, `FreePort.Eth` sessions, the ch. 22 clients' answers) with the cycle each took
    /// effect at into FILE (docs/replay.md).
    #[arg(long, value_name = "FILE")]
    record: Option<PathBuf>,
    /// Feed a `--record` FILE's inputs back at their cycles, without the outside peers
    /// (serial port 1's received bytes are dropped); implies `--clock sim`.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["record", "modbus_port"])]
    replay: Option<PathBuf>,
    /// Serve Modbus TCP (DXMC appendix A: DV, DH, the FUN147 image, DRL program control)
    /// on the machine file's `[modbus] bind` at this port; 0 asks the OS for a free one.
    #[arg(long)]
    modbus_port: Option<u16>,
}

/// A simulated run's outside inputs.
pub struct RunInputs {
    pub inputs: Arc<Inputs>,
    replay: Vec<Stamped>,
    record: Option<PathBuf>,
    replay_path: Option<PathBuf>,
    /// With `--record`: where the tasks write their `FreePort.Eth` inputs, one file each.
    freeport: Option<tempfile::TempDir>,
}

impl InputArgs {
    /// The clock of the run: `--replay` implies the simulation clock (at `speed`, `max`
    /// without it).
    pub fn clock(&self, clock: Clock, speed: Option<Speed>) -> Result<Clock> {
        match clock {
            Clock::RealTime if self.replay.is_some() => Ok(Clock::Sim { speed: speed.unwrap_or(Speed::Max) }),
            Clock::RealTime if self.record.is_some() => bail!("--record needs the simulation clock: --clock sim"),
            Clock::RealTime if speed.is_some() => bail!("--speed needs the simulation clock: --clock sim or --replay"),
            clock => Ok(clock),
        }
    }

    pub fn modbus_port(&self) -> Option<u16> {
        self.modbus_port
    }

    /// On the simulation clock: the inputs' queue, the record to replay (read and checked
    /// before anything starts) and where to write the run's.
    pub fn prepare(&self, clock: Clock) -> Result<Option<RunInputs>> {
        if clock == Clock::RealTime {
            return Ok(None);
        }
        let replay = match &self.replay {
            Some(path) => replay::read(path).with_context(|| format!("cannot replay {}", path.display()))?,
            None => Vec::new(),
        };
        let inputs = Inputs::new(self.record.is_some(), self.replay.is_some());
        let freeport = match self.record {
            Some(_) => Some(tempfile::Builder::new().prefix("luamotion-freeport-").tempdir()?),
            None => None,
        };
        Ok(Some(RunInputs { inputs, replay, record: self.record.clone(), replay_path: self.replay.clone(), freeport }))
    }
}

impl RunInputs {
    /// The lockstep gate's part: the Modbus writes.
    pub fn feed(&self) -> Feed {
        Feed::new(self.inputs.clone(), &self.replay)
    }

    /// Serial port 1's part: its received bytes stamped, recorded or replayed.
    pub fn serial(&self) -> serial::SimLine {
        let inputs = self.inputs.clone();
        let replay = self.inputs.replaying().then(|| {
            let serial = self.replay.iter().filter_map(|s| match &s.input {
                Input::Serial(bytes) => Some((s.cycle, bytes.clone())),
                _ => None,
            });
            serial.collect()
        });
        serial::SimLine {
            landing: self.inputs.landing(),
            record: Box::new(move |cycle, bytes| inputs.record(cycle, Input::Serial(bytes.to_vec()))),
            replay,
        }
    }

    /// What the script processes are told: where their `FreePort.Eth` inputs are recorded
    /// or replayed from.
    pub fn script_args(&self) -> Vec<String> {
        match (&self.freeport, &self.replay_path) {
            (Some(dir), _) => vec!["--freeport-record".into(), dir.path().display().to_string()],
            // Absolute: a script process may run elsewhere.
            (None, Some(path)) => {
                let path = std::path::absolute(path).unwrap_or_else(|_| path.clone());
                vec!["--freeport-replay".into(), path.display().to_string()]
            }
            (None, None) => Vec::new(),
        }
    }

    /// Writes the record (with `--record`), the tasks' `FreePort.Eth` and client inputs merged in.
    pub fn finish(&self) -> Result<()> {
        let Some(path) = &self.record else { return Ok(()) };
        if let Some(dir) = &self.freeport {
            for file in std::fs::read_dir(dir.path())? {
                let file = file?.path();
                let text = format!("{}\n{}", replay::HEADER, std::fs::read_to_string(&file)?);
                match replay::parse(text.as_bytes()) {
                    Ok(inputs) => inputs.into_iter().for_each(|s| self.inputs.record(s.cycle, s.input)),
                    Err(e) => eprintln!("warning: the task inputs of {} not recorded: {e}", file.display()),
                }
            }
        }
        let record = self.inputs.take_record();
        std::fs::write(path, replay::format(&record)).with_context(|| format!("write {}", path.display()))?;
        eprintln!("recorded {} input(s) into {}", record.len(), path.display());
        Ok(())
    }
}
