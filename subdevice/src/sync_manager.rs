//! SyncManagers (ETG.1000.4 6.7, table 59): the guard an ESC keeps on a window of its
//! process RAM that EtherCAT and the application share. A mailbox SyncManager (1-buffer)
//! takes one message at a time, a buffered one (3-buffer) always holds a whole, consistent
//! buffer. Which bytes EtherCAT may touch, and when a buffer or message is complete, is
//! decided here.

/// SyncManagers this ESC has.
pub const SM_COUNT: usize = 8;
/// Register bytes per SyncManager.
pub const SM_REGISTER_LEN: usize = 8;

/// One SyncManager's configuration, as its 8 registers hold it (table 59).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SmConfig {
    /// Physical start address.
    pub start: u16,
    /// Bytes in the window.
    pub length: u16,
    /// Control: mode in bits 0-1, direction in bits 2-3, interrupts, watchdog.
    pub control: u8,
    /// Activate: bit 0 enable, bit 1 repeat request.
    pub activate: u8,
}

/// Operation mode (control bits 0-1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmMode {
    /// 00: three buffers, EtherCAT always meets a complete one.
    Buffered,
    /// 10: one buffer, one message at a time.
    Mailbox,
}

/// Direction, as EtherCAT sees it (control bits 2-3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmDirection {
    /// 00: EtherCAT reads, the application writes.
    Read,
    /// 01: EtherCAT writes, the application reads.
    Write,
}

/// What an access from EtherCAT to a byte in an enabled window leads to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SmAccess {
    /// Refused: the datagram's byte stays as it is and does not count.
    Denied,
    /// Allowed.
    Allowed,
    /// Allowed, and it completed the buffer or message (its last byte).
    Completed,
}

impl SmConfig {
    /// Reads the 8 register bytes.
    pub fn from_registers(bytes: [u8; SM_REGISTER_LEN]) -> Self {
        SmConfig {
            start: u16::from_le_bytes([bytes[0], bytes[1]]),
            length: u16::from_le_bytes([bytes[2], bytes[3]]),
            control: bytes[4],
            activate: bytes[6],
        }
    }

    /// The mode; the reserved codes 01 and 11 are `None` (the window is not guarded).
    pub fn mode(&self) -> Option<SmMode> {
        match self.control & 0b11 {
            0b00 => Some(SmMode::Buffered),
            0b10 => Some(SmMode::Mailbox),
            _ => None,
        }
    }

    /// The direction; the reserved codes 10 and 11 are `None`.
    pub fn direction(&self) -> Option<SmDirection> {
        match (self.control >> 2) & 0b11 {
            0b00 => Some(SmDirection::Read),
            0b01 => Some(SmDirection::Write),
            _ => None,
        }
    }

    /// Enabled with a window, a valid mode and a valid direction.
    pub fn enabled(&self) -> bool {
        self.activate & 1 != 0 && self.length > 0 && self.mode().is_some() && self.direction().is_some()
    }

    /// Whether the window holds `address`.
    pub fn contains(&self, address: u16) -> bool {
        address >= self.start && u32::from(address) < u32::from(self.start) + u32::from(self.length)
    }

    /// The window's last byte, whose access completes a buffer or message.
    pub fn last(&self) -> u16 {
        self.start.wrapping_add(self.length.saturating_sub(1))
    }

    /// The activate register's repeat request bit (a master that lost a mailbox reply).
    pub fn repeat_request(&self) -> bool {
        self.activate & 0b10 != 0
    }
}

/// What an ESC keeps per SyncManager besides its registers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SmState {
    /// Mailbox: a message is in it (status bit 3).
    pub full: bool,
    /// Buffered: a complete buffer has been written since the window was enabled.
    pub written: bool,
}

impl SmState {
    /// An access from EtherCAT to `address` in the window of the enabled `config`.
    pub fn ecat_access(&mut self, config: &SmConfig, address: u16, write: bool) -> SmAccess {
        let (Some(mode), Some(direction)) = (config.mode(), config.direction()) else { return SmAccess::Allowed };
        let last = address == config.last();
        match (mode, direction, write) {
            // EtherCAT may only write a write window and read a read window.
            (_, SmDirection::Write, false) | (_, SmDirection::Read, true) => SmAccess::Denied,
            (SmMode::Mailbox, SmDirection::Write, true) if self.full => SmAccess::Denied,
            (SmMode::Mailbox, SmDirection::Read, false) if !self.full => SmAccess::Denied,
            (SmMode::Mailbox, SmDirection::Write, true) if last => {
                self.full = true;
                SmAccess::Completed
            }
            (SmMode::Mailbox, SmDirection::Read, false) if last => {
                self.full = false;
                SmAccess::Completed
            }
            (SmMode::Buffered, SmDirection::Write, true) if last => {
                self.written = true;
                SmAccess::Completed
            }
            (SmMode::Buffered, _, _) if last => SmAccess::Completed,
            _ => SmAccess::Allowed,
        }
    }

    /// The status register (0x0805 + 8n): bit 3 "mailbox full", bits 4-5 the buffered
    /// state (11: no buffer written yet, 00: the first).
    pub fn status(&self, config: &SmConfig) -> u8 {
        match config.mode() {
            Some(SmMode::Mailbox) => u8::from(self.full) << 3,
            Some(SmMode::Buffered) if !self.written => 0b11 << 4,
            _ => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SM0 and SM1 as the HIWIN drive's SII gives them (CoE manual table 2-2: the mailbox
    /// at 0x1800 and 0x18F6; SOEM's control bytes 0x26 and 0x22).
    fn sm0() -> SmConfig {
        SmConfig::from_registers([0x00, 0x18, 0xF6, 0x00, 0x26, 0x00, 0x01, 0x00])
    }

    fn sm1() -> SmConfig {
        SmConfig::from_registers([0xF6, 0x18, 0xF6, 0x00, 0x22, 0x00, 0x01, 0x00])
    }

    #[test]
    fn the_registers_give_mode_direction_and_window() {
        let config = sm0();
        assert_eq!((config.start, config.length, config.last()), (0x1800, 246, 0x18F5));
        assert_eq!((config.mode(), config.direction()), (Some(SmMode::Mailbox), Some(SmDirection::Write)));
        assert_eq!(sm1().direction(), Some(SmDirection::Read));
        assert!(config.enabled() && config.contains(0x1800) && config.contains(0x18F5) && !config.contains(0x18F6));
        let reserved = SmConfig { control: 0x01, ..config };
        assert!(!reserved.enabled(), "mode 01 is reserved");
    }

    /// A mailbox takes one message until it has been read, and gives one only when full.
    #[test]
    fn a_mailbox_holds_one_message() {
        let (write, read) = (sm0(), sm1());
        let mut rx = SmState::default();
        assert_eq!(rx.ecat_access(&write, 0x1800, true), SmAccess::Allowed);
        assert_eq!(rx.ecat_access(&write, 0x1800, false), SmAccess::Denied, "EtherCAT does not read a write mailbox");
        assert_eq!(rx.ecat_access(&write, 0x18F5, true), SmAccess::Completed);
        assert_eq!(rx.status(&write), 0x08);
        assert_eq!(rx.ecat_access(&write, 0x1800, true), SmAccess::Denied, "full");
        let mut tx = SmState::default();
        assert_eq!(tx.ecat_access(&read, 0x18F6, false), SmAccess::Denied, "empty");
        tx.full = true;
        assert_eq!(tx.ecat_access(&read, 0x18F6, false), SmAccess::Allowed);
        assert_eq!(tx.ecat_access(&read, 0x19EB, false), SmAccess::Completed);
        assert!(!tx.full);
    }

    #[test]
    fn a_buffer_is_complete_at_its_last_byte() {
        let outputs = SmConfig::from_registers([0x00, 0x10, 0x06, 0x00, 0x64, 0x00, 0x01, 0x00]);
        let mut state = SmState::default();
        assert_eq!(state.status(&outputs), 0x30, "no buffer yet");
        assert_eq!(state.ecat_access(&outputs, 0x1000, true), SmAccess::Allowed);
        assert_eq!(state.ecat_access(&outputs, 0x1005, true), SmAccess::Completed);
        assert_eq!(state.status(&outputs), 0x00);
        let inputs = SmConfig::from_registers([0x00, 0x11, 0x0A, 0x00, 0x20, 0x00, 0x01, 0x00]);
        assert_eq!(SmState::default().ecat_access(&inputs, 0x1100, true), SmAccess::Denied);
    }
}
