//! The simulated EtherCAT segment and its devices: the segment (`ecat/`: slaves, process
//! data, mailboxes, the network a master exchanges frames with), the CiA 402 servo drive
//! (`drive/`, behind its CoE object dictionary), the digital and analog I/O terminals, and
//! the bus the controller builds from the machine file (`bus.rs`).
//!
//! A master reaches these devices only through process data and SDOs. Nothing here knows
//! the motion kernel: the kernel and, later, the wire transport use this crate alike.

pub mod analog_terminal;
pub mod bus;
pub mod cia402;
pub mod coe;
pub mod drive;
pub mod ecat;
pub mod profile;
pub mod terminal;
