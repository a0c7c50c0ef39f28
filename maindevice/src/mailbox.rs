//! The mailbox on the wire (CoE manual 2.6): the cycle's SDO transfers, one after the
//! other on a thread of their own ("ecat-mailbox"), so that a transfer taking many frames
//! never holds up the process data. The cycle queues a request and takes the answer in a
//! later cycle (`devices::ecat::Network` files it by slave).

use std::sync::mpsc::{Receiver, SyncSender, TrySendError};

use devices::ecat::{SdoAbort, SdoAccess, SdoAnswer, SdoError, SdoRequest};
use ethercrab::error::{Error, MailboxError};

/// Transfers queued at once, each way; the cycle's queue refuses more (`MailboxBusy`).
pub const QUEUE: usize = 64;

/// The cycle's end of the mailbox queues.
pub struct CycleMailbox {
    requests: SyncSender<SdoRequest>,
    answers: Receiver<SdoAnswer>,
}

/// The mailbox thread's end.
pub struct WireMailbox {
    /// Transfers the cycle asked for, in order.
    pub requests: Receiver<SdoRequest>,
    /// Where their answers go.
    pub answers: SyncSender<SdoAnswer>,
}

/// Both ends; the channels are bounded, made once: sending never allocates.
pub fn queues() -> (CycleMailbox, WireMailbox) {
    let (requests_tx, requests) = std::sync::mpsc::sync_channel(QUEUE);
    let (answers, answers_rx) = std::sync::mpsc::sync_channel(QUEUE);
    (CycleMailbox { requests: requests_tx, answers: answers_rx }, WireMailbox { requests, answers })
}

impl CycleMailbox {
    /// Queues `request`; never waits.
    pub fn request(&self, request: SdoRequest) -> Result<(), SdoError> {
        match self.requests.try_send(request) {
            Ok(()) => Ok(()),
            Err(TrySendError::Full(_)) => Err(SdoError::MailboxBusy),
            // The master's thread is gone: the slave's device state refuses it.
            Err(TrySendError::Disconnected(_)) => Err(SdoError::Abort(SdoAbort::DeviceState)),
        }
    }

    /// The next answer, if one came; never waits.
    pub fn answer(&self) -> Option<SdoAnswer> {
        self.answers.try_recv().ok()
    }
}

/// One transfer through ethercrab: the bytes uploaded (zero-filled past the value) or why
/// it failed, as the in-memory mailbox would say it.
pub async fn transfer(
    subdevice: &ethercrab::SubDeviceRef<'_, impl std::ops::Deref<Target = ethercrab::SubDevice>>,
    request: SdoRequest,
) -> Result<([u8; 4], usize), SdoError> {
    let SdoRequest { index, sub, access, .. } = request;
    match access {
        SdoAccess::Upload => {
            let value: heapless::Vec<u8, 4> = subdevice.sdo_read(index, sub).await.map_err(sdo_error)?;
            let mut bytes = [0; 4];
            bytes[..value.len()].copy_from_slice(&value);
            Ok((bytes, value.len()))
        }
        SdoAccess::Download { data, len } => {
            let result = match len {
                1 => subdevice.sdo_write(index, sub, data[0]).await,
                2 => subdevice.sdo_write(index, sub, u16::from_le_bytes([data[0], data[1]])).await,
                4 => subdevice.sdo_write(index, sub, u32::from_le_bytes(data)).await,
                _ => return Err(SdoError::Abort(SdoAbort::LengthMismatch)),
            };
            result.map(|()| ([0; 4], 0)).map_err(sdo_error)
        }
    }
}

/// ethercrab's error as the CoE mailbox's: the slave's abort code (ETG.1000.6 table 41)
/// when it sent one, a protocol timeout when no answer came, else a general error.
pub fn sdo_error(error: Error) -> SdoError {
    let abort = match error {
        Error::Mailbox(MailboxError::Aborted { code, .. }) => {
            SdoAbort::try_from(u32::from(code)).unwrap_or(SdoAbort::General)
        }
        Error::Timeout(_) => SdoAbort::Timeout,
        _ => SdoAbort::General,
    };
    SdoError::Abort(abort)
}
