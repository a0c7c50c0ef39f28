//! The pseudo-terminal that is serial port 1: the controller holds the master, a peer
//! (socat, pyserial, minicom, mbpoll) opens the slave as it would a serial device. The
//! controller keeps a slave descriptor open too, so the master never reads EIO while no
//! peer is attached, and reads the slave's settings to see the frame the peer chose.
//!
//! A Linux pseudo-terminal keeps what a peer sets, except CSIZE and PARENB: the kernel
//! forces 8 bits without the parity flag on every change (drivers/tty/pty.c,
//! `pty_set_termios`). What stays says the parity all the same, where the peer set it:
//! PARODD is set only for odd parity, and INPCK (input parity checking) only with parity
//! on (libmodbus, and so mbpoll, sets it; pyserial clears it). So the line shows odd
//! (PARODD), even (INPCK without PARODD) or "none or even" (neither), docs/decisions.md
//! "Serial line settings".

use std::ffi::CStr;
use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::path::{Path, PathBuf};

use crate::protocol::{CharFrame, Parity};

/// A pseudo-terminal pair: the master the port's thread reads and writes, and a slave
/// kept open so the master never reads EIO while no peer is attached.
pub struct Pty {
    master: OwnedFd,
    slave: OwnedFd,
    path: PathBuf,
}

fn check(ret: libc::c_int) -> io::Result<libc::c_int> {
    if ret < 0 { Err(io::Error::last_os_error()) } else { Ok(ret) }
}

/// termios' speed constants of parameter 5-4's baud rates.
const SPEEDS: [(u32, libc::speed_t); 6] = [
    (4800, libc::B4800),
    (9600, libc::B9600),
    (19200, libc::B19200),
    (38400, libc::B38400),
    (57600, libc::B57600),
    (115_200, libc::B115200),
];

/// The line settings a peer sees and sets: character frame and baud rate (0 for one
/// parameter 5-4 does not have).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LineSettings {
    /// Data bits, parity and stop bits (parameter 5-1's frame).
    pub frame: CharFrame,
    /// The baud rate (parameter 5-4).
    pub baud: u32,
}

impl LineSettings {
    /// Whether a peer whose line reads as `seen` may be on this one (both as `Pty::line`
    /// reads them): the same settings, or no sign of parity where this line has even
    /// parity, since a peer may have set even parity without INPCK (pyserial does).
    pub fn admits(&self, seen: &LineSettings) -> bool {
        let unseen_even = LineSettings { frame: CharFrame { parity: Parity::None, ..self.frame }, ..*self };
        seen == self || (self.frame.parity == Parity::Even && *seen == unseen_even)
    }
}

impl std::fmt::Display for LineSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} at {} baud", self.frame, self.baud)
    }
}

impl Pty {
    /// A new pseudo-terminal in raw mode (no echo, no CR/LF translation) with `line`.
    pub fn open(line: LineSettings) -> io::Result<Pty> {
        // SAFETY: plain libc calls on a descriptor this function owns.
        unsafe {
            let fd = check(libc::posix_openpt(libc::O_RDWR | libc::O_NOCTTY | libc::O_NONBLOCK | libc::O_CLOEXEC))?;
            let master = OwnedFd::from_raw_fd(fd);
            check(libc::grantpt(fd))?;
            check(libc::unlockpt(fd))?;
            let mut name = [0 as libc::c_char; 128];
            let err = libc::ptsname_r(fd, name.as_mut_ptr(), name.len());
            if err != 0 {
                return Err(io::Error::from_raw_os_error(err));
            }
            let name = CStr::from_ptr(name.as_ptr());
            let slave = OwnedFd::from_raw_fd(check(libc::open(
                name.as_ptr(),
                libc::O_RDWR | libc::O_NOCTTY | libc::O_CLOEXEC,
            ))?);
            let path = PathBuf::from(name.to_string_lossy().into_owned());
            let pty = Pty { master, slave, path };
            pty.configure(line)?;
            Ok(pty)
        }
    }

    /// The slave's path, `/dev/pts/N`.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn termios(&self) -> io::Result<libc::termios> {
        // SAFETY: termios is plain data; tcgetattr fills it.
        let mut t: libc::termios = unsafe { std::mem::zeroed() };
        check(unsafe { libc::tcgetattr(self.slave.as_raw_fd(), &mut t) })?;
        Ok(t)
    }

    /// Sets the frame and speed of the line (at start and on a protocol change).
    pub fn configure(&self, line: LineSettings) -> io::Result<()> {
        let mut t = self.termios()?;
        // SAFETY: on a termios read from the device.
        unsafe {
            libc::cfmakeraw(&mut t);
            let speed = SPEEDS.iter().find(|(baud, _)| *baud == line.baud).map_or(libc::B38400, |(_, s)| *s);
            check(libc::cfsetispeed(&mut t, speed))?;
            check(libc::cfsetospeed(&mut t, speed))?;
        }
        t.c_cflag &= !(libc::CSIZE | libc::PARENB | libc::PARODD | libc::CSTOPB);
        t.c_cflag |= if line.frame.data_bits == 7 { libc::CS7 } else { libc::CS8 };
        t.c_cflag |= match line.frame.parity {
            Parity::None => 0,
            Parity::Even => libc::PARENB,
            Parity::Odd => libc::PARENB | libc::PARODD,
        };
        // What a pseudo-terminal keeps of the parity (see the top of this file).
        t.c_iflag &= !libc::INPCK;
        if line.frame.parity != Parity::None {
            t.c_iflag |= libc::INPCK;
        }
        if line.frame.stop_bits == 2 {
            t.c_cflag |= libc::CSTOPB;
        }
        t.c_cflag |= libc::CREAD | libc::CLOCAL;
        // SAFETY: a valid descriptor and termios.
        check(unsafe { libc::tcsetattr(self.slave.as_raw_fd(), libc::TCSANOW, &t) })?;
        Ok(())
    }

    /// The settings the line has now (the peer may have changed them). Parity: PARENB
    /// where the device keeps it, else PARODD for odd and INPCK for even; `None` on a
    /// pseudo-terminal may be even parity set without INPCK (`LineSettings::admits`).
    pub fn line(&self) -> io::Result<LineSettings> {
        let t = self.termios()?;
        let (parenb, parodd) = (t.c_cflag & libc::PARENB != 0, t.c_cflag & libc::PARODD != 0);
        let parity = match (parenb, parodd, t.c_iflag & libc::INPCK != 0) {
            (true, false, _) | (false, false, true) => Parity::Even,
            (_, true, _) => Parity::Odd,
            (false, false, false) => Parity::None,
        };
        let data_bits = if t.c_cflag & libc::CSIZE == libc::CS7 { 7 } else { 8 };
        let stop_bits = if t.c_cflag & libc::CSTOPB != 0 { 2 } else { 1 };
        // SAFETY: on a termios read from the device.
        let speed = unsafe { libc::cfgetospeed(&t) };
        let baud = SPEEDS.iter().find(|(_, s)| *s == speed).map_or(0, |(baud, _)| *baud);
        Ok(LineSettings { frame: CharFrame { data_bits, parity, stop_bits }, baud })
    }

    /// The master's descriptor, for poll(2).
    pub fn master_fd(&self) -> libc::c_int {
        self.master.as_raw_fd()
    }

    /// What the peer wrote, without waiting.
    pub fn read(&self, buf: &mut [u8]) -> io::Result<usize> {
        // SAFETY: a valid descriptor and buffer.
        let n = unsafe { libc::read(self.master.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len()) };
        check(n as libc::c_int).map(|_| n as usize)
    }

    /// Writes to the peer without waiting: what does not fit is lost, as on a line nobody
    /// listens to. Returns the bytes written.
    pub fn write(&self, bytes: &[u8]) -> usize {
        let mut written = 0;
        while written < bytes.len() {
            let rest = &bytes[written..];
            // SAFETY: a valid descriptor and buffer.
            let n = unsafe { libc::write(self.master.as_raw_fd(), rest.as_ptr().cast(), rest.len()) };
            match n {
                n if n > 0 => written += n as usize,
                _ if io::Error::last_os_error().kind() == io::ErrorKind::Interrupted => {}
                _ => break,
            }
        }
        written
    }
}

#[cfg(test)]
mod tests {
    use std::fs::OpenOptions;

    use super::*;

    /// Sets the line from the peer's end, as a serial program does (tcsetattr on its own
    /// descriptor of the slave), with `cflag` and `iflag` bits on or off.
    fn peer_sets(pty: &Pty, on: Flags, off: Flags) {
        let peer = OpenOptions::new().read(true).write(true).open(pty.path()).unwrap();
        let fd = peer.as_raw_fd();
        // SAFETY: termios is plain data; a valid descriptor.
        let mut t: libc::termios = unsafe { std::mem::zeroed() };
        check(unsafe { libc::tcgetattr(fd, &mut t) }).unwrap();
        t.c_cflag = (t.c_cflag | on.0) & !off.0;
        t.c_iflag = (t.c_iflag | on.1) & !off.1;
        // The ioctl itself: glibc's tcsetattr may report EINVAL for the PARENB the kernel dropped.
        check(unsafe { libc::ioctl(fd, libc::TCSETS, &t) }).unwrap();
    }

    fn frame(text: &str) -> CharFrame {
        let b = text.as_bytes();
        let parity = match b[2] {
            b'E' => Parity::Even,
            b'O' => Parity::Odd,
            _ => Parity::None,
        };
        CharFrame { data_bits: b[0] - b'0', parity, stop_bits: b[4] - b'0' }
    }

    /// The flags a peer turns on and off: (c_cflag, c_iflag).
    type Flags = (libc::tcflag_t, libc::tcflag_t);

    /// What the pseudo-terminal shows of each peer setting, and which the port admits.
    #[test]
    fn the_peer_s_parity_as_a_pseudo_terminal_shows_it() {
        use libc::{CSTOPB, INPCK, PARENB, PARODD};
        // Port frame, the peer's change (cflag, iflag on; cflag, iflag off), what reads, admitted.
        let rows: [(&str, Flags, Flags, &str, bool); 9] = [
            ("8,N,1", (0, 0), (0, 0), "8,N,1", true),
            ("8,N,1", (PARENB, 0), (PARODD, INPCK), "8,N,1", true), // pyserial's even: unseen
            ("8,N,1", (PARENB, INPCK), (PARODD, 0), "8,E,1", false), // libmodbus' even
            ("8,N,1", (PARENB | PARODD, 0), (0, INPCK), "8,O,1", false),
            ("8,N,1", (CSTOPB, 0), (0, 0), "8,N,2", false),
            ("8,E,1", (0, 0), (0, 0), "8,E,1", true),
            ("8,E,1", (PARENB, 0), (PARODD, INPCK), "8,N,1", true),
            ("8,E,1", (PARENB | PARODD, 0), (0, INPCK), "8,O,1", false),
            ("8,O,1", (PARENB, 0), (PARODD, INPCK), "8,N,1", false),
        ];
        for (port, on, off, reads, admitted) in rows {
            let line = LineSettings { frame: frame(port), baud: 38400 };
            let pty = Pty::open(line).unwrap();
            let expected = pty.line().unwrap();
            peer_sets(&pty, on, off);
            let seen = pty.line().unwrap();
            assert_eq!(seen.frame.to_string(), reads, "port {port}, peer {on:x?} {off:x?}");
            assert_eq!(expected.admits(&seen), admitted, "port {port}, peer reads {seen}");
        }
    }
}
