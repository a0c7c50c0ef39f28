//! One ESC (EtherCAT SubDevice Controller) in front of one `devices::ecat::Slave`: its
//! registers, process RAM guarded by SyncManagers and mapped by FMMUs, the SII EEPROM,
//! the mailbox and the distributed clock. The slave keeps its own state machine, object
//! dictionary and PDO mapping: an AL control write goes to `Slave::request_state`, an SDO
//! to `Slave::sdo_read`/`sdo_write`, the process data to `Slave::cycle`. What the ESC adds
//! are the data link layer's checks of the SyncManagers at Init to PreOp and PreOp to
//! SafeOp (CoE manual table 2-3), with their AL status codes.

use devices::coe::ObjectStore;
use devices::ecat::pdo::{Direction, PdoEntry};
use devices::ecat::slave::Slave;
use devices::ecat::{AlState, AlStatusCode};

use crate::command::{Addressing, Command, Done, Operation};
use crate::dc::DistributedClock;
use crate::fmmu::{FMMU_COUNT, FMMU_REGISTER_LEN, Fmmu};
use crate::frame::DatagramHeader;
use crate::mailbox::{MAILBOX_HEADER_LEN, Mailbox, SDO_LEN};
use crate::registers::*;
use crate::sii::{Eeprom, Identity, PdoDescription, PdoEntryDescription, SiiContents, SiiInterface, SmDescription};
use crate::sync_manager::{SM_COUNT, SM_REGISTER_LEN, SmAccess, SmConfig, SmDirection, SmMode, SmState};

/// Process RAM, 4 KiB from 0x1000.
pub const RAM_START: u32 = 0x1000;
/// Bytes of process RAM.
pub const RAM_LEN: usize = 0x1000;
/// SyncManager windows of the HIWIN drive (CoE manual table 2-2): the mailbox at 0x1800
/// and 0x18F6, as long as the gap between them, the process data at 0x1000 and 0x1100.
pub const MAILBOX_OUT: u16 = 0x1800;
/// SM1: the mailbox the slave answers in.
pub const MAILBOX_IN: u16 = 0x18F6;
/// Bytes of each mailbox.
pub const MAILBOX_LEN: u16 = MAILBOX_IN - MAILBOX_OUT;
/// SM2: outputs (RxPDOs).
pub const OUTPUTS: u16 = 0x1000;
/// SM3: inputs (TxPDOs).
pub const INPUTS: u16 = 0x1100;
/// Control bytes of the four SyncManagers as SOEM's defaults and the SII give them:
/// mailbox write/read with the ECAT interrupt, outputs buffered write with watchdog,
/// inputs buffered read.
const SM_CONTROL: [u8; 4] = [0x26, 0x22, 0x64, 0x20];

/// ESC type 0x04: a configurable ESC (an IP core), the closest kind to one in software
/// (docs/decisions.md, "ESC identity").
const ESC_TYPE: u8 = 0x04;
const ESC_REVISION: u8 = 0x01;
const ESC_BUILD: u16 = 0x0001;
/// Ports 0 and 1 MII, 2 and 3 not implemented (2 bits each).
const PORTS: u8 = 0b0000_1111;
/// Features (table 31): DC supported (bit 2), 64-bit DC (3), enhanced DC sync activation (8).
const FEATURES_SUPPORTED: u16 = 1 << 2 | 1 << 3 | 1 << 8;
/// DL control at power-up: non-EtherCAT frames are destroyed (bit 0).
const DL_CONTROL_RESET: u32 = 0x0000_0001;
/// DL control bit 24 (0x0103 bit 0): the station alias addresses the ESC too.
const ALIAS_ENABLE: u32 = 1 << 24;
/// DL status: PDI operational, link on port 0 (and 1), each port's loop and communication.
const DL_PDI_OPERATIONAL: u16 = 1 << 0;
const DL_LINK_PORT0: u16 = 1 << 4;
const DL_LINK_PORT1: u16 = 1 << 5;
/// Port n's loop (bit 8 + 2n, 1 = closed) and communication (bit 9 + 2n).
const fn port_open(n: u16) -> u16 {
    1 << (9 + 2 * n)
}
const fn port_closed(n: u16) -> u16 {
    1 << (8 + 2 * n)
}
/// AL status error indication (bit 4) and AL control's error acknowledge.
const AL_ERROR: u16 = 0x10;
/// AL status codes the ESC itself gives (ETG.1000.6 table 11).
const UNKNOWN_REQUESTED_STATE: u16 = 0x0012;
const BOOTSTRAP_NOT_SUPPORTED: u16 = 0x0013;
const INVALID_MAILBOX_CONFIGURATION: u16 = 0x0016;
const INVALID_OUTPUT_CONFIGURATION: u16 = 0x001D;
const INVALID_INPUT_CONFIGURATION: u16 = 0x001E;
/// The process data watchdog ran out (ETG.1000.6 table 11).
const SYNC_MANAGER_WATCHDOG: u16 = 0x001B;
/// SM control bit 6: the SyncManager's watchdog is on (SOEM's 0x64 for SM2 has it).
const SM_WATCHDOG_ENABLE: u8 = 0x40;
/// Power-up watchdog registers as an ESC has them: 2498 + 2 ticks of 40 ns make 100 us,
/// and 1000 of those the process data watchdog's 100 ms.
const WATCHDOG_DIVIDER_RESET: u16 = 2498;
const WATCHDOG_TIME_PROCESS_DATA_RESET: u16 = 1000;
/// SM PDI control bit 1: repeat acknowledge.
const REPEAT_ACK: u8 = 0b10;
/// The longest step of free run: a master that pauses does not see a drive leap.
const MAX_FREE_RUN_STEP_S: f64 = 0.1;
/// At most this many SYNC0 pulses are stepped per frame; a longer gap skips the rest.
pub const MAX_PULSES_PER_FRAME: u32 = 1000;

/// When a frame reaches this ESC: its port 0, and port 1 on its way back (`None` when
/// port 1 is closed: the last ESC of the line).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameArrival {
    /// Segment time the frame passes port 0 and the processing unit, ns.
    pub port0: u64,
    /// Segment time it returns through port 1.
    pub port1: Option<u64>,
}

/// What a datagram's access did that the ESC acts on when the datagram has passed.
#[derive(Clone, Copy, Debug, Default)]
struct Events {
    al_control: bool,
    sii_control: Option<u16>,
    latch: bool,
    system_time: Option<(u64, usize)>,
    sync_activation: bool,
    sm_activate: [bool; SM_COUNT],
    completed: [bool; SM_COUNT],
    sync0_status_read: bool,
}

/// One ESC and the slave behind it.
pub struct Esc {
    slave: Slave,
    registers: Registers,
    ram: Box<[u8; RAM_LEN]>,
    sms: [SmState; SM_COUNT],
    sii: SiiInterface,
    mailbox: Mailbox,
    dc: DistributedClock,
    /// SM2 and SM3 as accepted at PreOp to SafeOp.
    accepted: Option<[SmConfig; 2]>,
    /// An AL status code of the ESC's own checks, shown until the next accepted request.
    refusal: Option<u16>,
    /// The last complete output buffer (SM2), as long as the slave's outputs.
    outputs: Vec<u8>,
    inputs: Vec<u8>,
    /// Whether the frame under way reached the process data through an FMMU.
    process_data: bool,
    /// When the outputs were last written in Op (segment time): the process data
    /// watchdog's start.
    outputs_written: Option<u64>,
    last_step: Option<u64>,
    arrival: FrameArrival,
    last_port: bool,
    events: Events,
}

impl Esc {
    /// The ESC of `slave`, named `name` in its SII; `boot_ns` is how far its local clock
    /// is ahead of the segment's (ESCs power up at different moments).
    pub fn new(slave: Slave, name: &str, boot_ns: u64) -> Self {
        let mut registers = Registers::default();
        registers.set_byte(TYPE, ESC_TYPE);
        registers.set_byte(REVISION, ESC_REVISION);
        registers.set_u16(BUILD, ESC_BUILD);
        registers.set_byte(FMMUS_SUPPORTED, FMMU_COUNT as u8);
        registers.set_byte(SYNC_MANAGERS_SUPPORTED, SM_COUNT as u8);
        registers.set_byte(RAM_SIZE, (RAM_LEN / 1024) as u8);
        registers.set_byte(PORT_DESCRIPTOR, PORTS);
        registers.set_u16(FEATURES, FEATURES_SUPPORTED);
        registers.set_u32(DL_CONTROL, DL_CONTROL_RESET);
        registers.set_u16(WATCHDOG_DIVIDER, WATCHDOG_DIVIDER_RESET);
        registers.set_u16(WATCHDOG_TIME_PROCESS_DATA, WATCHDOG_TIME_PROCESS_DATA_RESET);
        let sii = SiiInterface::new(Eeprom::build(&sii_contents(slave.device().od(), name)), &mut registers);
        let mut esc = Esc {
            slave,
            registers,
            ram: Box::new([0; RAM_LEN]),
            sms: [SmState::default(); SM_COUNT],
            sii,
            mailbox: Mailbox::default(),
            dc: DistributedClock::new(boot_ns),
            accepted: None,
            refusal: None,
            outputs: Vec::new(),
            inputs: Vec::new(),
            process_data: false,
            outputs_written: None,
            last_step: None,
            arrival: FrameArrival::default(),
            last_port: true,
            events: Events::default(),
        };
        esc.render_status();
        esc
    }

    /// The slave behind the ESC.
    pub fn slave(&self) -> &Slave {
        &self.slave
    }

    /// The slave, for what the wire does not carry (the simulation's faults).
    pub fn slave_mut(&mut self) -> &mut Slave {
        &mut self.slave
    }

    /// The register file, as the ESC last rendered it.
    pub fn registers(&self) -> &Registers {
        &self.registers
    }

    /// The SII interface and its EEPROM.
    pub fn sii(&self) -> &SiiInterface {
        &self.sii
    }

    /// Whether port 1 leads on to another ESC (the DL status shows its link), or the
    /// frame turns back here.
    pub fn set_last(&mut self, last: bool) {
        self.last_port = last;
        self.render_status();
    }

    /// Whether the slave runs on SYNC0: it runs cyclically at a cycle the device takes
    /// (a drive synchronises to the DC cycles of its manual only).
    fn synchronised(&self) -> bool {
        self.dc.cycle_ns().is_some_and(|cycle| self.slave.device().accepts_cycle_time(i64::from(cycle)))
    }

    /// A frame reaches the ESC: the SYNC0 pulses until now step the slave first, so that
    /// the frame reads the inputs of the last pulse (DC mode; docs/decisions.md, "When the
    /// drives step").
    pub fn frame_arrives(&mut self, arrival: FrameArrival) {
        self.watch_process_data(arrival.port0);
        self.arrival = arrival;
        self.process_data = false;
        let pulses = self.dc.pulses(&mut self.registers, arrival.port0, MAX_PULSES_PER_FRAME);
        if !self.synchronised() {
            return;
        }
        for _ in 0..pulses.count {
            self.step(f64::from(pulses.cycle_ns) * 1e-9);
        }
        if pulses.count > 0 {
            self.last_step = Some(arrival.port0);
        }
    }

    /// The process data watchdog (ETG.1000.4 6.3): in Op, outputs not written for its
    /// time take the slave to SafeOp with 0x001B, and the device learns that the master's
    /// frames stopped. Looked at when a frame arrives: until then nothing could see it.
    fn watch_process_data(&mut self, now: u64) {
        if self.slave.esm().state() != AlState::Op || self.sm(2).control & SM_WATCHDOG_ENABLE == 0 {
            self.outputs_written = None;
            return;
        }
        let unit_ns = (u64::from(self.registers.u16(WATCHDOG_DIVIDER)) + 2) * 40;
        let time_ns = unit_ns * u64::from(self.registers.u16(WATCHDOG_TIME_PROCESS_DATA));
        let Some(written) = self.outputs_written else {
            self.outputs_written = Some(now);
            return;
        };
        if time_ns > 0 && now.saturating_sub(written) > time_ns {
            let _ = self.slave.request_state(AlState::SafeOp);
            self.refuse(SYNC_MANAGER_WATCHDOG);
            self.slave.process_data_lost();
            self.outputs_written = None;
        }
    }

    /// The frame has passed: not synchronised to SYNC0, a frame that reached the process
    /// data steps the slave once, by the time since its last step (free run).
    pub fn frame_leaves(&mut self) {
        if self.synchronised() || !self.process_data {
            return;
        }
        let now = self.arrival.port0;
        let period = self.last_step.map_or(0.0, |last| now.saturating_sub(last) as f64 * 1e-9);
        self.step(period.min(MAX_FREE_RUN_STEP_S));
        self.last_step = Some(now);
    }

    /// One datagram through this ESC: addressing (ADP counted up for position and
    /// broadcast commands), the access, the working counter. An unknown command passes
    /// untouched.
    pub fn datagram(&mut self, header: &mut DatagramHeader, data: &mut [u8], wkc: &mut u16) {
        let Ok(command) = Command::try_from(header.command) else { return };
        let alias = (self.registers.u32(DL_CONTROL) & ALIAS_ENABLE != 0).then(|| self.registers.u16(STATION_ALIAS));
        let arrival = command.arrive(header.adp(), self.registers.u16(STATION_ADDRESS), alias);
        header.set_adp(arrival.adp);
        self.render(self.arrival.port0);
        let operation = match (command.operation(), arrival.addressed) {
            (Operation::ReadMultipleWrite, true) => Operation::Read,
            (Operation::ReadMultipleWrite, false) => Operation::Write,
            (_, false) => return,
            (operation, true) => operation,
        };
        let or = command.addressing() == Addressing::Broadcast;
        let done = match command.addressing() {
            Addressing::Logical => self.logical(header.address, data, operation),
            _ => self.physical(header.ado(), data, operation, or),
        };
        *wkc = wkc.wrapping_add(command.working_counter(done));
        self.after_datagram();
    }

    /// Register and RAM access by address: reads replace the datagram's bytes (broadcast
    /// reads OR into them), writes take the datagram as it arrived (each byte is written
    /// before it is read into, so it is still the one that arrived).
    fn physical(&mut self, ado: u16, data: &mut [u8], operation: Operation, or: bool) -> Done {
        let mut done = Done::default();
        let (reads, writes) = sides(operation);
        for (i, byte) in data.iter_mut().enumerate() {
            let address = u32::from(ado) + i as u32;
            if writes && self.ecat_write(address, *byte) {
                done.written = true;
            }
            if reads && let Some(value) = self.ecat_read(address) {
                *byte = if or { *byte | value } else { value };
                done.read = true;
            }
        }
        done
    }

    /// Logical access through the FMMUs: all writes first, from the datagram as it
    /// arrived, then the reads into it, so that overlapping inputs replace outputs.
    fn logical(&mut self, address: u32, data: &mut [u8], operation: Operation) -> Done {
        let mut done = Done::default();
        let (reads, writes) = sides(operation);
        let fmmus: [Fmmu; FMMU_COUNT] = std::array::from_fn(|n| {
            Fmmu::from_registers(self.registers.bytes::<FMMU_REGISTER_LEN>(FMMU_BASE + (n * FMMU_REGISTER_LEN) as u16))
        });
        for fmmu in fmmus.iter().filter(|f| writes && f.writes()) {
            for run in fmmu.runs(address, data.len()) {
                let mask = (((1u16 << run.count) - 1) << run.physical_bit) as u8;
                let bits = (0..run.count).fold(0u8, |acc, k| {
                    let bit = run.datagram_bit + usize::from(k);
                    acc | ((data[bit / 8] >> (bit % 8)) & 1) << (run.physical_bit + k)
                });
                let value = (self.peek(run.physical) & !mask) | bits;
                if self.ecat_write(run.physical, value) {
                    done.written = true;
                    self.process_data = true;
                    self.outputs_written = Some(self.arrival.port0);
                }
            }
        }
        for fmmu in fmmus.iter().filter(|f| reads && f.reads()) {
            for run in fmmu.runs(address, data.len()) {
                let Some(value) = self.ecat_read(run.physical) else { continue };
                for k in 0..run.count {
                    let bit = run.datagram_bit + usize::from(k);
                    let set = (value >> (run.physical_bit + k)) & 1;
                    data[bit / 8] = (data[bit / 8] & !(1 << (bit % 8))) | set << (bit % 8);
                }
                done.read = true;
                self.process_data = true;
            }
        }
        done
    }

    /// The byte at `address` without any rule (the ESC's own view), 0 where no memory is.
    fn peek(&self, address: u32) -> u8 {
        match address {
            0..RAM_START => self.registers.byte(address as u16),
            _ => self.ram.get((address - RAM_START) as usize).copied().unwrap_or(0),
        }
    }

    /// The enabled SyncManager whose window holds `address`, if any. A window not wholly
    /// in the process RAM guards nothing (no application memory is behind it).
    fn guard(&self, address: u32) -> Option<(usize, SmConfig)> {
        let address = u16::try_from(address).ok()?;
        (0..SM_COUNT).map(|n| (n, self.sm(n))).find(|(_, c)| c.enabled() && c.contains(address) && window(c).is_some())
    }

    fn sm(&self, n: usize) -> SmConfig {
        SmConfig::from_registers(self.registers.bytes::<SM_REGISTER_LEN>(SM_BASE + (n * SM_REGISTER_LEN) as u16))
    }

    /// A read from EtherCAT; `None` where no memory is or a SyncManager refuses.
    fn ecat_read(&mut self, address: u32) -> Option<u8> {
        if address < RAM_START {
            if address == u32::from(DC_SYNC0_STATUS) {
                self.events.sync0_status_read = true;
            }
            return Some(self.registers.byte(address as u16));
        }
        let offset = usize::try_from(address - RAM_START).ok().filter(|&o| o < RAM_LEN)?;
        if let Some((n, config)) = self.guard(address) {
            match self.sms[n].ecat_access(&config, address as u16, false) {
                SmAccess::Denied => return None,
                SmAccess::Completed => self.events.completed[n] = true,
                SmAccess::Allowed => {}
            }
        }
        Some(self.ram[offset])
    }

    /// A write from EtherCAT; whether it counts. A register write counts even where the
    /// register is read-only (docs/decisions.md, "Protected registers").
    fn ecat_write(&mut self, address: u32, value: u8) -> bool {
        if address < RAM_START {
            self.register_write(address as u16, value);
            return true;
        }
        let Some(offset) = usize::try_from(address - RAM_START).ok().filter(|&o| o < RAM_LEN) else { return false };
        if let Some((n, config)) = self.guard(address) {
            match self.sms[n].ecat_access(&config, address as u16, true) {
                SmAccess::Denied => return false,
                SmAccess::Completed => self.events.completed[n] = true,
                SmAccess::Allowed => {}
            }
        }
        self.ram[offset] = value;
        true
    }

    fn register_write(&mut self, address: u16, value: u8) {
        let rule = self.registers.ecat_write(address, value);
        let events = &mut self.events;
        match address {
            0x0120..=0x0121 => events.al_control = true,
            0x0502..=0x0503 => {
                let shift = 8 * (address - SII_CONTROL);
                let old = events.sii_control.unwrap_or(0) & !(0xFF << shift);
                events.sii_control = Some(old | u16::from(value) << shift);
            }
            0x0900..=0x0903 => events.latch = true,
            0x0910..=0x0917 => {
                let (time, width) = events.system_time.unwrap_or((0, 0));
                let i = usize::from(address - DC_SYSTEM_TIME);
                events.system_time = Some((time | u64::from(value) << (8 * i), width.max(i + 1)));
            }
            0x0980..=0x0981 => events.sync_activation = true,
            0x0800..=0x083F if (address - SM_BASE) % 8 == 6 && rule == Writability::Stored => {
                events.sm_activate[usize::from((address - SM_BASE) / 8)] = true;
            }
            _ => {}
        }
    }

    /// What the datagram's accesses asked of the ESC, once it has passed.
    fn after_datagram(&mut self) {
        let events = std::mem::take(&mut self.events);
        if let Some(control) = events.sii_control {
            self.sii.control_written(&mut self.registers, control);
        }
        if events.latch {
            let ports = [Some(self.arrival.port0), self.arrival.port1, None, None];
            self.dc.latch(&mut self.registers, ports, self.arrival.port0);
        }
        if let Some((time, width)) = events.system_time {
            self.dc.compare(&mut self.registers, time, width, self.arrival.port0);
        }
        if events.sync_activation {
            let activation = self.registers.u16(DC_CYCLIC_UNIT_CONTROL);
            self.slave.write_esc_register(DC_CYCLIC_UNIT_CONTROL, activation);
            self.dc.activate(&mut self.registers, self.arrival.port0);
        }
        if events.sync0_status_read {
            self.dc.acknowledge();
        }
        for n in 0..SM_COUNT {
            if events.sm_activate[n] {
                self.sm_activated(n);
            }
            if events.completed[n] {
                self.sm_completed(n);
            }
        }
        if events.al_control {
            self.al_control();
        }
        self.deliver_reply();
        self.render_status();
    }

    /// An activate register written: a disabled SyncManager forgets its buffer; a toggled
    /// repeat request on SM1 puts the last reply back.
    fn sm_activated(&mut self, n: usize) {
        let config = self.sm(n);
        if !config.enabled() {
            self.sms[n] = SmState::default();
        }
        let pdi_control = SM_BASE + (n * SM_REGISTER_LEN) as u16 + 7;
        let ack = self.registers.byte(pdi_control) & REPEAT_ACK != 0;
        if n == 1 && config.enabled() && config.repeat_request() != ack {
            if let Some(reply) = self.mailbox.last_reply().map(<[u8]>::to_vec) {
                self.put_reply(&reply);
            }
            let pdi = self.registers.byte(pdi_control) ^ REPEAT_ACK;
            self.registers.set_byte(pdi_control, pdi);
        }
    }

    /// A buffer or message completed by EtherCAT: the application takes it at once.
    fn sm_completed(&mut self, n: usize) {
        let config = self.sm(n);
        let Some(window) = window(&config) else { return };
        match (config.mode(), config.direction()) {
            (Some(SmMode::Mailbox), Some(SmDirection::Write)) => {
                let message = self.ram[window].to_vec();
                self.sms[n].full = false;
                if self.slave.esm().state() != AlState::Init {
                    self.mailbox.receive(&message, &mut self.slave);
                }
            }
            (Some(SmMode::Buffered), Some(SmDirection::Write)) if n == 2 => {
                let len = self.outputs.len().min(window.len());
                self.outputs[..len].copy_from_slice(&self.ram[window][..len]);
            }
            _ => {}
        }
    }

    /// The next mailbox reply into SM1, when it is empty.
    fn deliver_reply(&mut self) {
        let config = self.sm(1);
        if !config.enabled() || self.sms[1].full || config.mode() != Some(SmMode::Mailbox) {
            return;
        }
        if let Some(reply) = self.mailbox.next_reply().map(<[u8]>::to_vec) {
            self.put_reply(&reply);
        }
    }

    fn put_reply(&mut self, reply: &[u8]) {
        let config = self.sm(1);
        let Some(window) = window(&config) else { return };
        let window = &mut self.ram[window];
        window.fill(0);
        let len = reply.len().min(window.len());
        window[..len].copy_from_slice(&reply[..len]);
        self.sms[1].full = true;
    }

    /// AL control written: a state request, carried out at once. While an error is shown,
    /// only a request with the acknowledge bit, or one to a lower state, is taken.
    fn al_control(&mut self) {
        let control = self.registers.u16(AL_CONTROL);
        let acknowledge = control & AL_ERROR != 0;
        let current = self.slave.esm().state();
        let target = match control & 0x0F {
            1 => AlState::Init,
            2 => AlState::PreOp,
            4 => AlState::SafeOp,
            8 => AlState::Op,
            3 => return self.refuse(BOOTSTRAP_NOT_SUPPORTED),
            _ => return self.refuse(UNKNOWN_REQUESTED_STATE),
        };
        if self.error_shown() && !acknowledge && target >= current {
            return;
        }
        if target == AlState::PreOp && current == AlState::Init && !self.mailbox_configured() {
            return self.refuse(INVALID_MAILBOX_CONFIGURATION);
        }
        if self.slave.request_state(target).is_err() {
            // The slave's own code shows (its ESM keeps it).
            self.refusal = None;
            return;
        }
        self.refusal = None;
        if target <= AlState::PreOp {
            self.accepted = None;
        }
        if target == AlState::Init {
            self.mailbox = Mailbox::default();
        }
        if current == AlState::PreOp && target == AlState::SafeOp {
            self.accept_process_data();
        }
    }

    /// PreOp to SafeOp: SM2 and SM3 must carry the slave's outputs and inputs as mapped.
    fn accept_process_data(&mut self) {
        let (rx_len, tx_len) = self.slave.pdo_lengths();
        let (outputs, inputs) = (self.sm(2), self.sm(3));
        let fits = |config: &SmConfig, len: usize, direction| {
            if len == 0 {
                return !config.enabled();
            }
            config.enabled()
                && usize::from(config.length) == len
                && config.mode() == Some(SmMode::Buffered)
                && config.direction() == Some(direction)
                && window(config).is_some()
        };
        let code = if !fits(&outputs, rx_len, SmDirection::Write) {
            Some(INVALID_OUTPUT_CONFIGURATION)
        } else if !fits(&inputs, tx_len, SmDirection::Read) {
            Some(INVALID_INPUT_CONFIGURATION)
        } else {
            None
        };
        match code {
            Some(code) => {
                // Back where the request came from; PreOp is always reachable from SafeOp.
                let _ = self.slave.request_state(AlState::PreOp);
                self.refuse(code);
            }
            None => {
                self.accepted = Some([outputs, inputs]);
                self.outputs = vec![0; rx_len];
                self.inputs = vec![0; tx_len];
            }
        }
    }

    /// Init to PreOp: SM0 a mailbox EtherCAT writes, SM1 one it reads, each long enough
    /// for an SDO and inside the RAM.
    fn mailbox_configured(&self) -> bool {
        let fits = |config: SmConfig, direction| {
            config.enabled()
                && config.mode() == Some(SmMode::Mailbox)
                && config.direction() == Some(direction)
                && usize::from(config.length) >= MAILBOX_HEADER_LEN + SDO_LEN
                && window(&config).is_some()
        };
        let (out, input) = (self.sm(0), self.sm(1));
        let end = |c: SmConfig| u32::from(c.start) + u32::from(c.length);
        let apart = end(out) <= u32::from(input.start) || end(input) <= u32::from(out.start);
        fits(out, SmDirection::Write) && fits(input, SmDirection::Read) && apart
    }

    fn refuse(&mut self, code: u16) {
        self.refusal = Some(code);
    }

    fn error_shown(&self) -> bool {
        self.refusal.is_some() || self.slave.esm().error().is_some()
    }

    /// One cycle of the slave: SafeOp and Op need SM2/SM3 as accepted (a master that
    /// changed them meets an ESC back in PreOp), outputs from the last complete buffer,
    /// inputs into SM3's window.
    fn step(&mut self, period_s: f64) {
        if self.slave.esm().state() >= AlState::SafeOp {
            let current = [self.sm(2), self.sm(3)];
            if self.accepted != Some(current) {
                let code = if self.accepted.is_some_and(|a| a[0] != current[0]) {
                    INVALID_OUTPUT_CONFIGURATION
                } else {
                    INVALID_INPUT_CONFIGURATION
                };
                let _ = self.slave.request_state(AlState::PreOp);
                self.accepted = None;
                self.refuse(code);
            }
        }
        let (rx_len, tx_len) = self.slave.pdo_lengths();
        self.outputs.resize(rx_len, 0);
        self.inputs.resize(tx_len, 0);
        self.slave.cycle(&self.outputs, &mut self.inputs, period_s);
        if let Some(window) = self.accepted.and_then(|[_, inputs]| window(&inputs)) {
            let len = self.inputs.len().min(window.len());
            self.ram[window][..len].copy_from_slice(&self.inputs[..len]);
        }
    }

    /// The registers an ESC computes, written in before a datagram reads them.
    fn render(&mut self, now: u64) {
        self.dc.render(&mut self.registers, now);
        self.render_status();
    }

    fn render_status(&mut self) {
        let esm = self.slave.esm();
        let code = self.refusal.or(esm.error().map(AlStatusCode::code));
        let error = if code.is_some() { AL_ERROR } else { 0 };
        self.registers.set_u16(AL_STATUS, u16::from(esm.state().code()) | error);
        self.registers.set_u16(AL_STATUS_CODE, code.unwrap_or(0));
        let port1 = if self.last_port { port_closed(1) } else { port_open(1) | DL_LINK_PORT1 };
        let status = DL_PDI_OPERATIONAL | DL_LINK_PORT0 | port_open(0) | port1 | port_closed(2) | port_closed(3);
        self.registers.set_u16(DL_STATUS, status);
        for n in 0..SM_COUNT {
            let status = self.sms[n].status(&self.sm(n));
            self.registers.set_byte(SM_BASE + (n * SM_REGISTER_LEN) as u16 + 5, status);
        }
    }
}

/// A SyncManager's window as a range of the process RAM, if it lies wholly in it.
fn window(config: &SmConfig) -> Option<std::ops::Range<usize>> {
    let start = usize::from(config.start).checked_sub(RAM_START as usize)?;
    let end = start + usize::from(config.length);
    (config.length > 0 && end <= RAM_LEN).then_some(start..end)
}

/// Which sides of an access an operation has: (reads, writes).
fn sides(operation: Operation) -> (bool, bool) {
    match operation {
        Operation::Read => (true, false),
        Operation::Write => (false, true),
        Operation::ReadWrite => (true, true),
        Operation::ReadMultipleWrite | Operation::NoOperation => (false, false),
    }
}

/// The EEPROM's contents from the device's dictionary: identity (0x1018), the default
/// PDO assignment (0x1C12/0x1C13) and the mappings it names, the SyncManagers of the CoE
/// manual's table 2-2 sized to them.
fn sii_contents(od: &ObjectStore, name: &str) -> SiiContents {
    let value = |index, sub| od.find(index, sub).map_or(0, |id| od.get(id));
    let identity = Identity {
        vendor: value(0x1018, 1) as u32,
        product: value(0x1018, 2) as u32,
        revision: value(0x1018, 3) as u32,
        serial: value(0x1018, 4) as u32,
    };
    let pdos = |direction: Direction, sync_manager| {
        let assignment = direction.assignment();
        (1..=value(assignment, 0).clamp(0, 255) as u8)
            .map(|k| value(assignment, k) as u16)
            .map(|index| PdoDescription {
                index,
                sync_manager,
                entries: (1..=value(index, 0).clamp(0, 255) as u8)
                    .map(|e| PdoEntry::from_u32(value(index, e) as u32))
                    .filter_map(|entry| {
                        let id = od.find(entry.index, entry.sub)?;
                        Some(PdoEntryDescription { index: entry.index, sub: entry.sub, ty: od.def(id).ty })
                    })
                    .collect(),
            })
            .collect::<Vec<_>>()
    };
    let (rx_pdos, tx_pdos) = (pdos(Direction::Outputs, 2), pdos(Direction::Inputs, 3));
    let bytes = |pdos: &[PdoDescription]| pdos.iter().flat_map(|p| &p.entries).map(|e| e.ty.bytes() as u16).sum();
    let sm =
        |n: usize, start, length, kind| SmDescription { start, length, control: SM_CONTROL[n], enable: true, kind };
    SiiContents {
        identity,
        name: name.to_string(),
        sync_managers: [
            sm(0, MAILBOX_OUT, MAILBOX_LEN, 1),
            sm(1, MAILBOX_IN, MAILBOX_LEN, 2),
            sm(2, OUTPUTS, bytes(&rx_pdos), 3),
            sm(3, INPUTS, bytes(&tx_pdos), 4),
        ],
        rx_pdos,
        tx_pdos,
    }
}
