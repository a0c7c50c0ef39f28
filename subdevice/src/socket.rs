//! The segment on a network interface: a raw AF_PACKET socket bound to the interface for
//! EtherType 0x88A4 (it needs CAP_NET_RAW), each frame processed and sent back out of the
//! interface it came in, as the first ESC's port 0 returns it to the master.

use std::io;
use std::os::fd::{AsFd, AsRawFd, FromRawFd, OwnedFd};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::frame::ETHERTYPE;
use crate::segment::Segment;

/// Room for the longest Ethernet frame without its checksum, and more.
pub const FRAME_BUFFER_LEN: usize = 2048;
/// How often `serve` looks at its stop flag while no frame comes.
const POLL: Duration = Duration::from_millis(100);

/// Why the segment could not get on the interface.
#[derive(Debug, thiserror::Error)]
pub enum SocketError {
    /// No such interface (or its name is too long).
    #[error("no network interface {name:?}: {error}")]
    Interface {
        /// The name asked for.
        name: String,
        /// What the kernel said.
        error: io::Error,
    },
    /// The raw socket was refused: it needs CAP_NET_RAW.
    #[error("a raw socket (AF_PACKET) was refused: {0} (it needs CAP_NET_RAW)")]
    Open(io::Error),
    /// Binding to the interface or joining its promiscuous mode failed.
    #[error("binding the raw socket to {name:?}: {error}")]
    Bind {
        /// The interface.
        name: String,
        /// What the kernel said.
        error: io::Error,
    },
}

/// A raw socket on one interface, for EtherCAT frames only.
pub struct RawSocket {
    fd: OwnedFd,
}

/// The kernel's answer of a libc call: its value, or errno.
fn check(result: libc::c_int) -> io::Result<libc::c_int> {
    if result < 0 { Err(io::Error::last_os_error()) } else { Ok(result) }
}

impl RawSocket {
    /// Opens the socket on `interface`, receiving every EtherCAT frame on it whatever its
    /// destination (promiscuous for as long as the socket lives).
    pub fn bind(interface: &str) -> Result<Self, SocketError> {
        let name = std::ffi::CString::new(interface).map_err(|e| SocketError::Interface {
            name: interface.to_string(),
            error: io::Error::new(io::ErrorKind::InvalidInput, e),
        })?;
        // SAFETY: a C string that lives through the call.
        let index = unsafe { libc::if_nametoindex(name.as_ptr()) };
        if index == 0 {
            return Err(SocketError::Interface { name: interface.to_string(), error: io::Error::last_os_error() });
        }
        let protocol = ETHERTYPE.to_be();
        // SAFETY: plain arguments; the descriptor is owned at once.
        let fd = check(unsafe { libc::socket(libc::AF_PACKET, libc::SOCK_RAW | libc::SOCK_CLOEXEC, protocol.into()) })
            .map_err(SocketError::Open)?;
        // SAFETY: a new descriptor nobody else owns.
        let fd = unsafe { OwnedFd::from_raw_fd(fd) };
        let bind_error = |error| SocketError::Bind { name: interface.to_string(), error };
        // SAFETY: zeroed is a valid sockaddr_ll; the fields set are the ones bind reads.
        let mut address: libc::sockaddr_ll = unsafe { std::mem::zeroed() };
        address.sll_family = libc::AF_PACKET as u16;
        address.sll_protocol = protocol;
        address.sll_ifindex = index as i32;
        // SAFETY: the address and its size, of the type AF_PACKET takes.
        check(unsafe {
            libc::bind(
                fd.as_raw_fd(),
                (&address as *const libc::sockaddr_ll).cast(),
                std::mem::size_of::<libc::sockaddr_ll>() as libc::socklen_t,
            )
        })
        .map_err(bind_error)?;
        // SAFETY: zeroed is a valid packet_mreq; the fields set are the ones the call reads.
        let mut membership: libc::packet_mreq = unsafe { std::mem::zeroed() };
        membership.mr_ifindex = index as i32;
        membership.mr_type = libc::PACKET_MR_PROMISC as u16;
        // SAFETY: the option value and its size.
        check(unsafe {
            libc::setsockopt(
                fd.as_raw_fd(),
                libc::SOL_PACKET,
                libc::PACKET_ADD_MEMBERSHIP,
                (&membership as *const libc::packet_mreq).cast(),
                std::mem::size_of::<libc::packet_mreq>() as libc::socklen_t,
            )
        })
        .map_err(bind_error)?;
        Ok(RawSocket { fd })
    }

    /// The next frame that came in on the interface, waiting at most `timeout`; `None`
    /// when none came.
    pub fn receive(&self, buffer: &mut [u8], timeout: Duration) -> io::Result<Option<usize>> {
        let mut poll = libc::pollfd { fd: self.fd.as_raw_fd(), events: libc::POLLIN, revents: 0 };
        // SAFETY: one pollfd.
        let ready = check(unsafe { libc::poll(&mut poll, 1, timeout.as_millis().min(i32::MAX as u128) as i32) });
        match ready {
            Ok(0) => return Ok(None),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => return Ok(None),
            Err(e) => return Err(e),
            Ok(_) => {}
        }
        // SAFETY: zeroed is a valid sockaddr_ll for recvfrom to fill.
        let mut from: libc::sockaddr_ll = unsafe { std::mem::zeroed() };
        let mut from_len = std::mem::size_of::<libc::sockaddr_ll>() as libc::socklen_t;
        // SAFETY: the buffer and the address with their sizes.
        let n = unsafe {
            libc::recvfrom(
                self.fd.as_raw_fd(),
                buffer.as_mut_ptr().cast(),
                buffer.len(),
                libc::MSG_DONTWAIT,
                (&mut from as *mut libc::sockaddr_ll).cast(),
                &mut from_len,
            )
        };
        if n < 0 {
            let error = io::Error::last_os_error();
            return match error.kind() {
                io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted => Ok(None),
                _ => Err(error),
            };
        }
        // The frames this socket sent itself are not requests.
        Ok((from.sll_pkttype != libc::PACKET_OUTGOING).then_some(n as usize))
    }

    /// Sends one frame out of the interface.
    pub fn send(&self, frame: &[u8]) -> io::Result<()> {
        // SAFETY: the frame and its length.
        let n = unsafe { libc::send(self.fd.as_raw_fd(), frame.as_ptr().cast(), frame.len(), 0) };
        if n < 0 { Err(io::Error::last_os_error()) } else { Ok(()) }
    }
}

impl AsFd for RawSocket {
    fn as_fd(&self) -> std::os::fd::BorrowedFd<'_> {
        self.fd.as_fd()
    }
}

/// Nanoseconds of CLOCK_MONOTONIC: the segment's clock on a wire.
pub fn monotonic_ns() -> u64 {
    let mut now = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: a timespec to fill; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut now) };
    now.tv_sec as u64 * 1_000_000_000 + now.tv_nsec as u64
}

/// What a run of `serve` saw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Served {
    /// Frames answered.
    pub answered: u64,
    /// Frames dropped as broken.
    pub dropped: u64,
    /// Answers the interface refused (its link was down): lost as on a pulled cable.
    pub unsent: u64,
}

/// The interface's link as `serve` last met it. A pulled cable or an interface set down
/// is waited out, as an ESC waits for its link to come back; only a change is logged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Link {
    Up,
    Down,
}

impl Link {
    fn met(&mut self, now: Link, why: Option<&io::Error>) {
        if *self != now {
            match why {
                Some(error) => tracing::warn!("the segment's link is down ({error}); waiting for it"),
                None => tracing::info!("the segment's link is up again"),
            }
            *self = now;
        }
    }
}

/// An error of a link that is down for now, not of the socket: the network down (the
/// interface set down, ETG.1000.4's lost link) or no room to send. An interface that is
/// gone (ENODEV) is not: it never comes back under this socket.
fn link_is_down(error: &io::Error) -> bool {
    matches!(error.raw_os_error(), Some(libc::ENETDOWN | libc::ENXIO | libc::ENOBUFS | libc::EAGAIN))
}

/// Serves the segment on the socket until `stop` is set: every frame that comes in is
/// processed at the monotonic clock's time and sent back; a broken one is dropped. While
/// the link is down the segment waits for it; an error of the socket itself ends it.
pub fn serve(segment: &mut Segment, socket: &RawSocket, stop: &AtomicBool) -> io::Result<Served> {
    let mut buffer = [0u8; FRAME_BUFFER_LEN];
    let mut served = Served::default();
    let mut link = Link::Up;
    while !stop.load(Ordering::Relaxed) {
        let n = match socket.receive(&mut buffer, POLL) {
            Ok(Some(n)) => n,
            Ok(None) => continue,
            Err(error) if link_is_down(&error) => {
                link.met(Link::Down, Some(&error));
                // The kernel reports a link going down once; this only keeps a link that
                // keeps failing from spinning.
                std::thread::sleep(POLL / 10);
                continue;
            }
            Err(error) => return Err(error),
        };
        let frame = &mut buffer[..n];
        match segment.process(frame, monotonic_ns()) {
            Ok(()) => match socket.send(frame) {
                Ok(()) => {
                    link.met(Link::Up, None);
                    served.answered += 1;
                }
                Err(error) if link_is_down(&error) => {
                    link.met(Link::Down, Some(&error));
                    served.unsent += 1;
                }
                Err(error) => return Err(error),
            },
            Err(error) => {
                tracing::debug!("frame of {n} bytes dropped: {error}");
                served.dropped += 1;
            }
        }
    }
    Ok(served)
}
