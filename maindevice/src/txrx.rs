//! ethercrab's PDU loop on a raw socket ("ecat-txrx"). ethercrab's own `tx_rx_task` ends
//! at the first frame that matches no PDU in flight, and a wire brings such frames: a
//! frame duplicated on the way, or the late answer to one the master has given up on and
//! sent again. Here such a frame is counted and dropped, as an EtherCAT master drops a
//! frame it did not send, and the loop goes on.

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::task::{Context, Poll};
use std::time::Duration;

use async_io::Async;
use ethercrab::error::Error;
use ethercrab::{PduRx, PduTx};
use subdevice::RawSocket;
use subdevice::socket::FRAME_BUFFER_LEN;

/// The loop until the MainDevice asks it to end (`release_all`).
pub struct TxRx<'a> {
    socket: Async<RawSocket>,
    tx: PduTx<'a>,
    rx: PduRx<'a>,
    buffer: Box<[u8; FRAME_BUFFER_LEN]>,
    unmatched: Arc<AtomicU64>,
    /// The interface refused the last frame.
    link_down: bool,
}

impl<'a> TxRx<'a> {
    /// The loop over `socket`; frames that match nothing in flight are counted in `unmatched`.
    pub fn new(socket: RawSocket, tx: PduTx<'a>, rx: PduRx<'a>, unmatched: Arc<AtomicU64>) -> std::io::Result<Self> {
        let buffer = Box::new([0; FRAME_BUFFER_LEN]);
        Ok(TxRx { socket: Async::new(socket)?, tx, rx, buffer, unmatched, link_down: false })
    }
}

impl Future for TxRx<'_> {
    type Output = ();

    fn poll(self: Pin<&mut Self>, context: &mut Context<'_>) -> Poll<()> {
        let this = self.get_mut();
        this.tx.replace_waker(context.waker());
        if this.tx.should_exit() {
            return Poll::Ready(());
        }
        while let Some(frame) = this.tx.next_sendable_frame() {
            let (socket, link_down) = (this.socket.get_ref(), &mut this.link_down);
            // A frame the interface refuses (its link is down) is lost as on a pulled
            // cable: ethercrab's timeout and resends deal with it, as with any lost frame.
            let _ = frame.send_blocking(|data| {
                match socket.send(data) {
                    Ok(()) if *link_down => {
                        *link_down = false;
                        tracing::info!("EtherCAT: the interface sends again");
                    }
                    Ok(()) => {}
                    Err(error) if !*link_down => {
                        *link_down = true;
                        tracing::warn!("EtherCAT: the interface refuses frames ({error}); they count as lost");
                    }
                    Err(_) => {}
                }
                Ok::<usize, Error>(data.len())
            });
        }
        loop {
            match this.socket.poll_readable(context) {
                Poll::Pending => return Poll::Pending,
                Poll::Ready(Err(error)) => {
                    tracing::error!("EtherCAT socket: {error}");
                    return Poll::Ready(());
                }
                Poll::Ready(Ok(())) => {}
            }
            while let Ok(Some(n)) = this.socket.get_ref().receive(&mut this.buffer[..], Duration::ZERO) {
                if this.rx.receive_frame(&this.buffer[..n]).is_err() {
                    this.unmatched.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
    }
}
