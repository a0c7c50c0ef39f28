//! The EtherCAT commands (ETG.1000.4 5.4, tables 14-28): how each addresses an ESC, what it
//! does with the datagram's data there, and what the ESC adds to the working counter.

use num_enum::TryFromPrimitive;

/// The command codes of ETG.1000.4 5.4. A code no table lists is an error
/// (`TryFromPrimitive`): such a datagram passes every ESC unprocessed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, TryFromPrimitive)]
#[repr(u8)]
pub enum Command {
    /// No operation (table 28): no ESC touches the datagram.
    Nop = 0,
    /// Auto increment physical read (table 14).
    Aprd = 1,
    /// Auto increment physical write (table 15).
    Apwr = 2,
    /// Auto increment physical read write (table 16).
    Aprw = 3,
    /// Configured address physical read (table 17).
    Fprd = 4,
    /// Configured address physical write (table 18).
    Fpwr = 5,
    /// Configured address physical read write (table 19).
    Fprw = 6,
    /// Broadcast read (table 20).
    Brd = 7,
    /// Broadcast write (table 21).
    Bwr = 8,
    /// Broadcast read write (table 22).
    Brw = 9,
    /// Logical memory read (table 23).
    Lrd = 10,
    /// Logical memory write (table 24).
    Lwr = 11,
    /// Logical memory read write (table 25).
    Lrw = 12,
    /// Auto increment physical read multiple write (table 26).
    Armw = 13,
    /// Configured address physical read multiple write (table 27).
    Frmw = 14,
}

/// How a command picks the ESCs it acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Addressing {
    /// ADP is a position: the ESC that finds it 0 is addressed; every ESC increments it.
    Position,
    /// ADP is a configured station address (0x0010) or, with DL control's alias bit, the
    /// station alias (0x0012); nobody changes it.
    Configured,
    /// Every ESC is addressed; every ESC increments ADP.
    Broadcast,
    /// The 32-bit address is logical: the ESC's FMMUs decide.
    Logical,
    /// NOP: no ESC.
    NoEsc,
}

/// What an addressed ESC does with the data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operation {
    /// Puts its memory into the datagram.
    Read,
    /// Puts the datagram into its memory.
    Write,
    /// Both: memory to datagram, datagram (as it arrived) to memory.
    ReadWrite,
    /// The addressed ESC reads, every other ESC writes (ARMW, FRMW: a clock distributed).
    ReadMultipleWrite,
    /// Nothing.
    NoOperation,
}

/// What one ESC did with one datagram, for the working counter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Done {
    /// At least one bit of memory went into the datagram.
    pub read: bool,
    /// At least one bit of the datagram went into memory.
    pub written: bool,
}

/// Where an ESC stands to one datagram.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Arrival {
    /// The ESC is addressed (for logical commands: it checks its FMMUs).
    pub addressed: bool,
    /// ADP as the datagram leaves this ESC.
    pub adp: u16,
}

impl Command {
    /// How the command addresses ESCs.
    pub fn addressing(self) -> Addressing {
        use Command::*;
        match self {
            Aprd | Apwr | Aprw | Armw => Addressing::Position,
            Fprd | Fpwr | Fprw | Frmw => Addressing::Configured,
            Brd | Bwr | Brw => Addressing::Broadcast,
            Lrd | Lwr | Lrw => Addressing::Logical,
            Nop => Addressing::NoEsc,
        }
    }

    /// What the command does at an addressed ESC.
    pub fn operation(self) -> Operation {
        use Command::*;
        match self {
            Aprd | Fprd | Brd | Lrd => Operation::Read,
            Apwr | Fpwr | Bwr | Lwr => Operation::Write,
            Aprw | Fprw | Brw | Lrw => Operation::ReadWrite,
            Armw | Frmw => Operation::ReadMultipleWrite,
            Nop => Operation::NoOperation,
        }
    }

    /// Whether the ESC is addressed by `adp` and what it forwards: position and broadcast
    /// commands count ADP up at every ESC, configured ones leave it (ETG.1000.4 5.4.1).
    /// `alias` is the station alias when DL control enables it.
    pub fn arrive(self, adp: u16, station: u16, alias: Option<u16>) -> Arrival {
        match self.addressing() {
            Addressing::Position => Arrival { addressed: adp == 0, adp: adp.wrapping_add(1) },
            Addressing::Broadcast => Arrival { addressed: true, adp: adp.wrapping_add(1) },
            Addressing::Configured => Arrival { addressed: adp == station || alias == Some(adp), adp },
            Addressing::Logical => Arrival { addressed: true, adp },
            Addressing::NoEsc => Arrival { addressed: false, adp },
        }
    }

    /// The working counter an ESC adds (each table's "WKC" row): a read counts 1, a write
    /// 1, and for the read-write commands the write counts 2, so that 3 means both; for
    /// ARMW and FRMW the reading ESC and each writing ESC count 1.
    pub fn working_counter(self, done: Done) -> u16 {
        let (read, written) = (u16::from(done.read), u16::from(done.written));
        match self.operation() {
            Operation::Read => read,
            Operation::Write => written,
            Operation::ReadWrite => read + 2 * written,
            Operation::ReadMultipleWrite => read + written,
            Operation::NoOperation => 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_etg_1000_4_s_and_others_are_unknown() {
        assert_eq!(Command::try_from(0x0C), Ok(Command::Lrw));
        assert_eq!(Command::try_from(0x0E), Ok(Command::Frmw));
        assert!(Command::try_from(0x0F).is_err());
        assert!(Command::try_from(0xFF).is_err());
    }

    /// The working counter, one row per command family.
    #[test]
    fn working_counter_rules() {
        let (none, read, written) =
            (Done::default(), Done { read: true, written: false }, Done { read: false, written: true });
        let both = Done { read: true, written: true };
        let rows = [
            (Command::Fprd, read, 1),
            (Command::Fprd, written, 0),
            (Command::Bwr, written, 1),
            (Command::Lrw, read, 1),
            (Command::Lrw, written, 2),
            (Command::Lrw, both, 3),
            (Command::Aprw, both, 3),
            (Command::Frmw, read, 1),
            (Command::Armw, written, 1),
            (Command::Nop, both, 0),
            (Command::Lrd, none, 0),
        ];
        for (command, done, wkc) in rows {
            assert_eq!(command.working_counter(done), wkc, "{command:?} {done:?}");
        }
    }

    #[test]
    fn position_and_broadcast_count_adp_up_configured_leaves_it() {
        assert_eq!(Command::Aprd.arrive(0, 0x1001, None), Arrival { addressed: true, adp: 1 });
        assert_eq!(Command::Aprd.arrive(0xFFFF, 0x1001, None), Arrival { addressed: false, adp: 0 });
        assert_eq!(Command::Brd.arrive(7, 0, None), Arrival { addressed: true, adp: 8 });
        assert_eq!(Command::Fprd.arrive(0x1001, 0x1001, None), Arrival { addressed: true, adp: 0x1001 });
        assert_eq!(Command::Fprd.arrive(0x0007, 0x1001, Some(7)), Arrival { addressed: true, adp: 7 });
        assert!(!Command::Fprd.arrive(0x0007, 0x1001, None).addressed);
        assert!(!Command::Nop.arrive(0, 0, None).addressed);
    }
}
