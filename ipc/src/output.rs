//! Program output on its way from a script process to the operator: lines of at most
//! `MAX_LINE_BYTES`, a longer one cut with a marker that says how much was left out. The
//! script process cuts what it writes and the controller cuts what it reads, with the same
//! `Lines`, so that neither holds more than one bounded line whatever a program prints.

use std::fmt::Write;

/// The bytes of a line that are kept; the rest is counted in the marker.
pub const MAX_LINE_BYTES: usize = 4096;

/// Room for the marker: a line the script process cut is not cut again by the controller.
pub const MARKER_BYTES: usize = 48;

/// What stands at the end of a cut line.
pub fn cut_marker(bytes: u64) -> String {
    format!(" … [cut: {bytes} bytes]")
}

/// Keeps at most `limit` bytes of what is pushed (never half a UTF-8 character) and
/// counts the rest.
pub struct Capped {
    limit: usize,
    kept: Vec<u8>,
    cut: u64,
    /// The kept part is full: what comes now only counts.
    full: bool,
}

impl Capped {
    /// Keeps at most `limit` bytes.
    pub fn new(limit: usize) -> Self {
        Capped { limit, kept: Vec::new(), cut: 0, full: false }
    }

    /// Adds bytes: kept while there is room, counted as cut after.
    pub fn push(&mut self, bytes: &[u8]) {
        if self.full {
            self.cut += bytes.len() as u64;
            return;
        }
        let room = self.limit - self.kept.len();
        if bytes.len() <= room {
            self.kept.extend_from_slice(bytes);
            return;
        }
        let n = char_boundary(bytes, room);
        self.kept.extend_from_slice(&bytes[..n]);
        self.cut += (bytes.len() - n) as u64;
        self.full = true;
    }

    /// The bytes kept.
    pub fn kept(&self) -> &[u8] {
        &self.kept
    }

    /// The bytes pushed but not kept.
    pub fn cut(&self) -> u64 {
        self.cut
    }

    /// Nothing was pushed since the last `clear`.
    pub fn is_empty(&self) -> bool {
        self.kept.is_empty() && self.cut == 0
    }

    /// Starts over, empty.
    pub fn clear(&mut self) {
        self.kept.clear();
        self.cut = 0;
        self.full = false;
    }
}

/// Splits a byte stream into lines, each `Capped`.
pub struct Lines {
    line: Capped,
}

impl Lines {
    /// Cuts each line at `limit` bytes.
    pub fn new(limit: usize) -> Self {
        Lines { line: Capped::new(limit) }
    }

    /// Takes the next bytes of the stream; `line` gets each line that ends in them (without
    /// its newline) and the number of its bytes that were cut.
    pub fn feed(&mut self, mut bytes: &[u8], mut line: impl FnMut(&[u8], u64)) {
        while !bytes.is_empty() {
            match memchr::memchr(b'\n', bytes) {
                Some(i) => {
                    self.line.push(&bytes[..i]);
                    self.emit(&mut line);
                    bytes = &bytes[i + 1..];
                }
                None => {
                    self.line.push(bytes);
                    bytes = &[];
                }
            }
        }
    }

    /// Ends the stream: a last line without a newline still counts.
    pub fn finish(&mut self, mut line: impl FnMut(&[u8], u64)) {
        if !self.line.is_empty() {
            self.emit(&mut line);
        }
    }

    fn emit(&mut self, line: &mut impl FnMut(&[u8], u64)) {
        line(self.line.kept(), self.line.cut());
        self.line.clear();
    }
}

/// The largest `n <= max` that does not split a UTF-8 character of `bytes` (bytes that are
/// no UTF-8 may be split anywhere).
pub fn char_boundary(bytes: &[u8], max: usize) -> usize {
    if max >= bytes.len() {
        return bytes.len();
    }
    // A continuation byte (0b10xx_xxxx) belongs to the character before it; one has 3 at most.
    let mut n = max;
    while n > 0 && max - n < 3 && bytes[n] & 0xC0 == 0x80 {
        n -= 1;
    }
    if bytes[n] & 0xC0 == 0x80 { max } else { n }
}

/// A line as a terminal may show it: control characters other than tab, and bytes that
/// are no UTF-8, as escapes. A backslash stays as it is.
pub fn escape(line: &[u8]) -> String {
    let mut out = String::with_capacity(line.len());
    for chunk in line.utf8_chunks() {
        for c in chunk.valid().chars() {
            match c {
                '\t' => out.push(c),
                '\r' => out.push_str("\\r"),
                c if c.is_control() => {
                    let _ = write!(out, "\\x{:02x}", c as u32);
                }
                c => out.push(c),
            }
        }
        for b in chunk.invalid() {
            let _ = write!(out, "\\x{b:02x}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(limit: usize, chunks: &[&[u8]]) -> Vec<(String, u64)> {
        let mut out = Vec::new();
        let mut lines = Lines::new(limit);
        for chunk in chunks {
            lines.feed(chunk, |l, cut| out.push((String::from_utf8_lossy(l).into_owned(), cut)));
        }
        lines.finish(|l, cut| out.push((String::from_utf8_lossy(l).into_owned(), cut)));
        out
    }

    #[test]
    fn long_lines_are_cut_and_counted_across_chunks() {
        let long = vec![b'x'; 10_000];
        let got = lines(8, &[b"ab\ncd", &long, b"ef\n", b"tail"]);
        assert_eq!(got, vec![("ab".into(), 0), ("cdxxxxxx".into(), 10_000 + 2 - 6), ("tail".into(), 0)]);
    }

    #[test]
    fn a_cut_never_splits_a_character() {
        // "é" is two bytes: a limit of 3 keeps "aé" (3 bytes), a limit of 2 keeps "a".
        assert_eq!(lines(3, &["aéé".as_bytes()]), vec![("aé".into(), 2)]);
        assert_eq!(lines(2, &["aéé".as_bytes()]), vec![("a".into(), 4)]);
        // Bytes that are no UTF-8 are cut where the limit is.
        assert_eq!(char_boundary(&[0x80; 10], 5), 5);
    }

    #[test]
    fn control_characters_are_escaped() {
        assert_eq!(escape(b"a\rb\x1b[2J\tc\x7f"), "a\\rb\\x1b[2J\tc\\x7f");
        // C1 controls (U+0080..U+009F, e.g. the 8-bit CSI) are control characters too.
        assert_eq!(escape("\u{9b}2J \\".as_bytes()), "\\x9b2J \\");
    }
}
