//! Slaves behind a wire: what the master's view (`Network`) needs of another transport.
//! The network keeps its image, its layout and its device models (as a real master keeps
//! its ESI files); the wire carries the frames and the mailbox, and never makes the cycle
//! wait: process data is handed over, SDOs are queued and answered in a later cycle.

use crate::ecat::esm::AlState;
use crate::ecat::mailbox::SdoError;

/// What one cycle's exchange of process data gave (ETG.1000.4 5.4: the working counter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Exchange {
    /// A frame came back since the last exchange, and every slave counted in it.
    Fresh,
    /// A frame came back, but short of the working counter planned: a slave is lost, or
    /// its process data is not in the image.
    WorkingCounter {
        /// What came back.
        found: u16,
        /// What the plan expects.
        expected: u16,
    },
    /// No frame came back in time: the cable, a lost frame, or the master's thread was
    /// late. The inputs are the last ones.
    Missing,
}

/// One SDO transfer through a slave's mailbox (CoE manual 2.6), at most 4 bytes: the
/// expedited transfer every object the controller writes in steady state fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SdoRequest {
    /// Ring position.
    pub slave: u16,
    /// The object's index.
    pub index: u16,
    /// Its sub-index.
    pub sub: u8,
    /// Upload or download.
    pub access: SdoAccess,
}

/// The direction of an SDO transfer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SdoAccess {
    /// Read the object.
    Upload,
    /// Write `len` bytes of `data`, little-endian.
    Download {
        /// The value's bytes.
        data: [u8; 4],
        /// How many of them: the object's width.
        len: u8,
    },
}

/// A finished transfer: the request, and the bytes read or why it failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SdoAnswer {
    /// What was asked.
    pub request: SdoRequest,
    /// The bytes uploaded, little-endian, and how many (0 for a download), or the failure.
    pub result: Result<([u8; 4], usize), SdoError>,
}

/// A segment reached over a wire. Every method returns at once.
pub trait Remote: Send {
    /// Hands `outputs` over for the next frame and takes the inputs of the last one.
    fn exchange(&mut self, outputs: &[u8], inputs: &mut [u8]) -> Exchange;
    /// Queues an SDO transfer; `SdoError::MailboxBusy` when the queue is full.
    fn request(&mut self, request: SdoRequest) -> Result<(), SdoError>;
    /// The next finished transfer, in the order they finished.
    fn answer(&mut self) -> Option<SdoAnswer>;
    /// The lowest AL state the slaves reported in the last frame that came back.
    fn state(&self) -> AlState;
    /// Frames that came back matching nothing sent: duplicated on the way, or late.
    fn unmatched(&self) -> u64;
}
