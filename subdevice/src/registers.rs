//! The ESC register file a master reads and writes (ETG.1000.4 clause 6: DL information
//! table 31, station address table 32, DL control table 33, DL status table 34, AL control
//! and status table 35, SII interface table 48, FMMU table 57, SyncManager table 59,
//! distributed clock tables 60 and 61), and which of its bytes EtherCAT may write.
//!
//! The bytes are the store of everything a master configures; what an ESC computes (AL
//! status, SyncManager status, the clock) its owner writes in before a read.

/// Bytes of register space, 0x0000-0x0FFF; process RAM follows.
pub const REGISTERS_LEN: usize = 0x1000;

/// Type of the ESC (DL information, table 31).
pub const TYPE: u16 = 0x0000;
/// Revision of the ESC.
pub const REVISION: u16 = 0x0001;
/// Build of the ESC (16 bits).
pub const BUILD: u16 = 0x0002;
/// Number of FMMUs the ESC has.
pub const FMMUS_SUPPORTED: u16 = 0x0004;
/// Number of SyncManagers the ESC has.
pub const SYNC_MANAGERS_SUPPORTED: u16 = 0x0005;
/// Process RAM in KiB.
pub const RAM_SIZE: u16 = 0x0006;
/// Port descriptor: 2 bits per port.
pub const PORT_DESCRIPTOR: u16 = 0x0007;
/// ESC features supported (16 bits).
pub const FEATURES: u16 = 0x0008;
/// Configured station address (table 32).
pub const STATION_ADDRESS: u16 = 0x0010;
/// Configured station alias, loaded from SII word 4; read-only for EtherCAT.
pub const STATION_ALIAS: u16 = 0x0012;
/// DL control (table 33, 32 bits): forwarding, loop settings, alias enable (bit 24).
pub const DL_CONTROL: u16 = 0x0100;
/// DL status (table 34).
pub const DL_STATUS: u16 = 0x0110;
/// AL control (table 35).
pub const AL_CONTROL: u16 = 0x0120;
/// AL status.
pub const AL_STATUS: u16 = 0x0130;
/// AL status code.
pub const AL_STATUS_CODE: u16 = 0x0134;
/// PDI control, loaded from SII word 0.
pub const PDI_CONTROL: u16 = 0x0140;
/// SII EEPROM configuration: bit 0 offers the EEPROM to the PDI (table 48).
pub const SII_CONFIG: u16 = 0x0500;
/// SII EEPROM PDI access state.
pub const SII_PDI_ACCESS: u16 = 0x0501;
/// SII control/status (16 bits).
pub const SII_CONTROL: u16 = 0x0502;
/// SII word address (32 bits).
pub const SII_ADDRESS: u16 = 0x0504;
/// SII data (8 bytes read, 2 written).
pub const SII_DATA: u16 = 0x0508;
/// The first FMMU (16 bytes each, table 57).
pub const FMMU_BASE: u16 = 0x0600;
/// Watchdog divider: 40 ns ticks, less 2, of one watchdog unit (ETG.1000.4 6.3).
pub const WATCHDOG_DIVIDER: u16 = 0x0400;
/// Process data watchdog time, in watchdog units; 0 turns it off (ETG.1000.4 6.3).
pub const WATCHDOG_TIME_PROCESS_DATA: u16 = 0x0420;
/// The first SyncManager (8 bytes each, table 59).
pub const SM_BASE: u16 = 0x0800;
/// Port 0 receive time; a write latches every port's (table 60).
pub const DC_RECEIVE_TIME_PORT0: u16 = 0x0900;
/// System time (64 bits); a write is compared, not stored.
pub const DC_SYSTEM_TIME: u16 = 0x0910;
/// Local time at which the frame that latched the receive times reached the processing unit.
pub const DC_RECEIVE_TIME_PU: u16 = 0x0918;
/// System time offset (64 bits).
pub const DC_SYSTEM_TIME_OFFSET: u16 = 0x0920;
/// System time delay (32 bits).
pub const DC_SYSTEM_TIME_DELAY: u16 = 0x0928;
/// System time difference (32 bits: bit 31 the sign, the rest the magnitude).
pub const DC_SYSTEM_TIME_DIFFERENCE: u16 = 0x092C;
/// Cyclic unit control (table 61).
pub const DC_CYCLIC_UNIT_CONTROL: u16 = 0x0980;
/// Sync activation: bit 0 cyclic operation, bit 1 SYNC0, bit 2 SYNC1.
pub const DC_ACTIVATION: u16 = 0x0981;
/// Sync activation status.
pub const DC_ACTIVATION_STATUS: u16 = 0x0984;
/// SYNC0 status: bit 0 a pulse since the last read.
pub const DC_SYNC0_STATUS: u16 = 0x098E;
/// Start time of cyclic operation as written; the next SYNC0 pulse as read (64 bits).
pub const DC_START_TIME: u16 = 0x0990;
/// SYNC0 cycle time in ns (32 bits).
pub const DC_SYNC0_CYCLE: u16 = 0x09A0;

/// What a write from EtherCAT does to one register byte.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Writability {
    /// Stored as written.
    Stored,
    /// Any write clears it (the error and watchdog counters).
    Clears,
    /// Not stored; the write is an event the ESC acts on (SII command, receive time latch,
    /// system time compare).
    Event,
    /// Read-only for EtherCAT (or reserved): the write is ignored.
    ReadOnly,
}

/// A SyncManager's bytes 0-5 (start, length, control, status) can only be written while
/// it is disabled; its activate byte always.
const SM_LOCKED_WHILE_ENABLED: core::ops::Range<u16> = 0..5;

/// Which register bytes EtherCAT may write (ETG.1000.4 clause 6; the rest of 0x0000-0x0FFF
/// is reserved or read-only and ignores writes).
pub fn writability(address: u16) -> Writability {
    use Writability::*;
    match address {
        0x0010..=0x0011 => Stored,
        0x0100..=0x0103 | 0x0108..=0x0109 => Stored,
        0x0120..=0x0121 => Stored,
        0x0200..=0x0201 => Stored,
        0x0300..=0x0313 => Clears,
        0x0400..=0x0401 | 0x0410..=0x0411 | 0x0420..=0x0421 => Stored,
        0x0442..=0x0443 => Clears,
        0x0500 | 0x0504..=0x0507 | 0x0508..=0x0509 => Stored,
        // The SII control word: a command the EEPROM interface carries out.
        0x0502..=0x0503 => Event,
        0x0600..=0x067F => match address % 16 {
            // Bytes 13-15 of each FMMU are reserved.
            0..=12 => Stored,
            _ => ReadOnly,
        },
        0x0800..=0x083F => match address % 8 {
            // Status (5) and PDI control (7) belong to the ESC.
            5 | 7 => ReadOnly,
            _ => Stored,
        },
        0x0900..=0x0903 => Event,
        0x0910..=0x0917 => Event,
        0x0920..=0x092B => Stored,
        0x0930..=0x0931 | 0x0934..=0x0935 => Stored,
        0x0980..=0x0981 => Stored,
        0x0990..=0x0997 => Stored,
        0x09A0..=0x09A7 => Stored,
        0x09A8..=0x09A9 => Stored,
        _ => ReadOnly,
    }
}

/// The register bytes.
#[derive(Clone)]
pub struct Registers {
    bytes: Box<[u8; REGISTERS_LEN]>,
}

impl Default for Registers {
    fn default() -> Self {
        Registers { bytes: Box::new([0; REGISTERS_LEN]) }
    }
}

impl Registers {
    /// One byte.
    pub fn byte(&self, address: u16) -> u8 {
        self.bytes.get(usize::from(address)).copied().unwrap_or(0)
    }

    /// Sets one byte from the ESC's own side (no write rule).
    pub fn set_byte(&mut self, address: u16, value: u8) {
        if let Some(byte) = self.bytes.get_mut(usize::from(address)) {
            *byte = value;
        }
    }

    /// `N` bytes from `address`, little-endian on the wire.
    pub fn bytes<const N: usize>(&self, address: u16) -> [u8; N] {
        std::array::from_fn(|i| self.byte(address.wrapping_add(i as u16)))
    }

    /// Writes `N` bytes from the ESC's own side.
    pub fn set_bytes(&mut self, address: u16, value: &[u8]) {
        for (i, &b) in value.iter().enumerate() {
            self.set_byte(address.wrapping_add(i as u16), b);
        }
    }

    /// A 16-bit register.
    pub fn u16(&self, address: u16) -> u16 {
        u16::from_le_bytes(self.bytes(address))
    }

    /// A 32-bit register.
    pub fn u32(&self, address: u16) -> u32 {
        u32::from_le_bytes(self.bytes(address))
    }

    /// A 64-bit register.
    pub fn u64(&self, address: u16) -> u64 {
        u64::from_le_bytes(self.bytes(address))
    }

    /// Sets a 16-bit register from the ESC's side.
    pub fn set_u16(&mut self, address: u16, value: u16) {
        self.set_bytes(address, &value.to_le_bytes());
    }

    /// Sets a 32-bit register from the ESC's side.
    pub fn set_u32(&mut self, address: u16, value: u32) {
        self.set_bytes(address, &value.to_le_bytes());
    }

    /// Sets a 64-bit register from the ESC's side.
    pub fn set_u64(&mut self, address: u16, value: u64) {
        self.set_bytes(address, &value.to_le_bytes());
    }

    /// A write from EtherCAT of one byte, by the rule of `writability`; a SyncManager's
    /// configuration bytes only while it is disabled. Returns what the write was.
    pub fn ecat_write(&mut self, address: u16, value: u8) -> Writability {
        let rule = writability(address);
        if (SM_BASE..SM_BASE + 0x40).contains(&address) {
            let offset = (address - SM_BASE) % 8;
            let enabled = self.byte(address - offset + 6) & 1 != 0;
            if enabled && SM_LOCKED_WHILE_ENABLED.contains(&offset) {
                return Writability::ReadOnly;
            }
        }
        match rule {
            Writability::Stored => self.set_byte(address, value),
            Writability::Clears => self.set_byte(address, 0),
            Writability::Event | Writability::ReadOnly => {}
        }
        rule
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One row per kind of register: what a write from EtherCAT leaves.
    #[test]
    fn protected_registers_keep_their_value() {
        let mut registers = Registers::default();
        registers.set_byte(TYPE, 0x11);
        registers.set_u16(STATION_ALIAS, 0x0007);
        registers.set_u16(AL_STATUS, 0x0002);
        registers.set_byte(0x0300, 5);
        let rows = [
            (TYPE, Writability::ReadOnly, 0x11),
            (STATION_ALIAS, Writability::ReadOnly, 0x07),
            (AL_STATUS, Writability::ReadOnly, 0x02),
            (STATION_ADDRESS, Writability::Stored, 0xAB),
            (0x0300, Writability::Clears, 0),
            (DC_SYSTEM_TIME, Writability::Event, 0),
            (0x060D, Writability::ReadOnly, 0),
            (0x0805, Writability::ReadOnly, 0),
            (0x0F00, Writability::ReadOnly, 0),
        ];
        for (address, rule, after) in rows {
            assert_eq!(registers.ecat_write(address, 0xAB), rule, "0x{address:04X}");
            assert_eq!(registers.byte(address), after, "0x{address:04X}");
        }
    }

    #[test]
    fn an_enabled_sync_manager_keeps_its_configuration() {
        let mut registers = Registers::default();
        registers.ecat_write(SM_BASE + 2, 0x10);
        registers.ecat_write(SM_BASE + 6, 0x01);
        assert_eq!(registers.ecat_write(SM_BASE + 2, 0x20), Writability::ReadOnly);
        assert_eq!(registers.byte(SM_BASE + 2), 0x10);
        assert_eq!(registers.ecat_write(SM_BASE + 6, 0x00), Writability::Stored);
        assert_eq!(registers.ecat_write(SM_BASE + 2, 0x20), Writability::Stored);
        assert_eq!(registers.u16(SM_BASE + 2), 0x20);
    }
}
