//! The printf subset of HMPL's `Print`, `StringPrint` and `SendMsgEvent` (HMPL ch. 3):
//! `%d %i %u %x %c %s %f %e %g %%`, with C's flags, width and precision.
//!
//! Formatting never holds more than one output line in Rust memory, outside the task's
//! Lua memory limit: a width or precision beyond `MAX_FIELD` is a bad format, `%s` reads
//! its string in place, and the text is kept up to `ipc::output::MAX_LINE_BYTES` (the rest
//! is counted). Bytes that are no UTF-8 pass through as they are; the controller shows
//! them escaped.

use std::borrow::Cow;
use std::fmt::Write;

use ipc::output::{Capped, MAX_LINE_BYTES};

/// HMPL 3.1: no HMPL string is longer than `HMPL_STR_MAX_LEN` (512) characters, so no field
/// of one is either; a wider width or precision is a bad format (HMPL 3.2: -1).
pub const MAX_FIELD: usize = 512;

/// One argument, as a script passed it.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg<'a> {
    Int(i64),
    Float(f64),
    Str(&'a [u8]),
}

#[derive(Debug, PartialEq, Eq, thiserror::Error)]
pub enum FormatError {
    #[error("format needs more arguments than the {0} given")]
    MissingArgument(usize),
    #[error("%{0} expects a number")]
    NotANumber(char),
    #[error("unknown conversion %{0}")]
    UnknownConversion(char),
    #[error("format ends inside a conversion")]
    Truncated,
    #[error("a width or precision above {MAX_FIELD} (HMPL_STR_MAX_LEN)")]
    FieldTooWide,
}

/// The formatted text, kept up to one output line.
#[derive(Debug)]
pub struct Formatted {
    /// The text's first bytes.
    pub text: Vec<u8>,
    /// The bytes of the text beyond `text`.
    pub cut: u64,
    /// The whole text's characters (a byte that is no UTF-8 counts as one).
    pub chars: usize,
}

#[derive(Default)]
struct Spec {
    left: bool,
    plus: bool,
    space: bool,
    alt: bool,
    zero: bool,
    width: usize,
    precision: Option<usize>,
}

/// The text being formatted and its length in characters.
struct Out {
    text: Capped,
    chars: usize,
}

impl Out {
    fn push(&mut self, bytes: &[u8]) {
        self.chars += chars(bytes);
        self.text.push(bytes);
    }

    fn repeat(&mut self, byte: u8, n: usize) {
        for _ in 0..n {
            self.push(&[byte]);
        }
    }
}

/// Formats like C's `sprintf`. Extra arguments are ignored, as the manual says.
pub fn format(fmt: &[u8], args: &[Arg]) -> Result<Formatted, FormatError> {
    let mut out = Out { text: Capped::new(MAX_LINE_BYTES), chars: 0 };
    let mut next = args.iter();
    let mut i = 0;
    while i < fmt.len() {
        let literal = fmt[i..].iter().position(|&b| b == b'%').unwrap_or(fmt.len() - i);
        out.push(&fmt[i..i + literal]);
        i += literal + 1;
        if i > fmt.len() {
            break;
        }
        let mut spec = Spec::default();
        while let Some(&f) = fmt.get(i) {
            match f {
                b'-' => spec.left = true,
                b'+' => spec.plus = true,
                b' ' => spec.space = true,
                b'#' => spec.alt = true,
                b'0' => spec.zero = true,
                _ => break,
            }
            i += 1;
        }
        spec.width = field(fmt, &mut i)?.unwrap_or(0);
        if fmt.get(i) == Some(&b'.') {
            i += 1;
            spec.precision = Some(field(fmt, &mut i)?.unwrap_or(0));
        }
        // Length modifiers (h, l, ll) change nothing for Lua's 64-bit numbers.
        while matches!(fmt.get(i), Some(b'h' | b'l')) {
            i += 1;
        }
        let conversion = match fmt.get(i) {
            None => return Err(FormatError::Truncated),
            Some(&b) if b.is_ascii() => b as char,
            Some(_) => return Err(FormatError::UnknownConversion(first_char(&fmt[i..]))),
        };
        i += 1;
        if conversion == '%' {
            out.push(b"%");
            continue;
        }
        let arg = next.next().ok_or(FormatError::MissingArgument(args.len()))?;
        let body = convert(conversion, &spec, arg)?;
        pad(&mut out, &spec, &body, conversion);
    }
    Ok(Formatted { text: out.text.kept().to_vec(), cut: out.text.cut(), chars: out.chars })
}

/// A width or a precision: digits, at most `MAX_FIELD`.
fn field(fmt: &[u8], i: &mut usize) -> Result<Option<usize>, FormatError> {
    let mut n: Option<usize> = None;
    while let Some(d) = fmt.get(*i).filter(|b| b.is_ascii_digit()) {
        n = Some(n.unwrap_or(0).saturating_mul(10).saturating_add((d - b'0') as usize));
        *i += 1;
    }
    match n {
        Some(n) if n > MAX_FIELD => Err(FormatError::FieldTooWide),
        n => Ok(n),
    }
}

/// The characters of `bytes`: UTF-8 characters, and each byte that is none.
fn chars(bytes: &[u8]) -> usize {
    bytes.utf8_chunks().map(|c| c.valid().chars().count() + c.invalid().len()).sum()
}

/// The first `n` characters of `bytes`, counted as `chars` does.
fn first_chars(bytes: &[u8], mut n: usize) -> &[u8] {
    let mut end = 0;
    for chunk in bytes.utf8_chunks() {
        for (at, _) in chunk.valid().char_indices() {
            if n == 0 {
                return &bytes[..end + at];
            }
            n -= 1;
        }
        end += chunk.valid().len();
        let invalid = chunk.invalid().len().min(n);
        end += invalid;
        n -= invalid;
        if n == 0 {
            return &bytes[..end];
        }
    }
    bytes
}

fn first_char(bytes: &[u8]) -> char {
    bytes.utf8_chunks().next().and_then(|c| c.valid().chars().next()).unwrap_or(char::REPLACEMENT_CHARACTER)
}

fn as_text(bytes: &[u8]) -> Option<&str> {
    std::str::from_utf8(bytes).ok().map(str::trim)
}

fn as_int(arg: &Arg, conversion: char) -> Result<i64, FormatError> {
    match arg {
        Arg::Int(i) => Ok(*i),
        Arg::Float(f) => Ok(f.trunc() as i64),
        Arg::Str(s) => as_text(s).and_then(|s| s.parse().ok()).ok_or(FormatError::NotANumber(conversion)),
    }
}

fn as_float(arg: &Arg, conversion: char) -> Result<f64, FormatError> {
    match arg {
        Arg::Int(i) => Ok(*i as f64),
        Arg::Float(f) => Ok(*f),
        Arg::Str(s) => as_text(s).and_then(|s| s.parse().ok()).ok_or(FormatError::NotANumber(conversion)),
    }
}

/// The bits a 64-bit C target prints for `%u`/`%x`: an `int` that fits is taken as 32 bits.
fn as_unsigned(v: i64) -> u64 {
    if (i32::MIN as i64..0).contains(&v) { v as u32 as u64 } else { v as u64 }
}

fn convert<'a>(conversion: char, spec: &Spec, arg: &Arg<'a>) -> Result<Cow<'a, [u8]>, FormatError> {
    let sign = |negative: bool| {
        if negative {
            "-"
        } else if spec.plus {
            "+"
        } else if spec.space {
            " "
        } else {
            ""
        }
    };
    let text = match conversion {
        'd' | 'i' => {
            let v = as_int(arg, conversion)?;
            format!("{}{}", sign(v < 0), v.unsigned_abs())
        }
        'u' => as_unsigned(as_int(arg, conversion)?).to_string(),
        'x' => {
            let v = as_unsigned(as_int(arg, conversion)?);
            if spec.alt && v != 0 { format!("0x{v:x}") } else { format!("{v:x}") }
        }
        'X' => {
            let v = as_unsigned(as_int(arg, conversion)?);
            if spec.alt && v != 0 { format!("0X{v:X}") } else { format!("{v:X}") }
        }
        'c' => char::from_u32(as_int(arg, conversion)? as u32).map(String::from).unwrap_or_default(),
        's' => {
            let s: Cow<[u8]> = match arg {
                Arg::Str(s) => Cow::Borrowed(s),
                Arg::Int(i) => Cow::Owned(i.to_string().into_bytes()),
                Arg::Float(f) => Cow::Owned(f.to_string().into_bytes()),
            };
            return Ok(match (spec.precision, s) {
                (Some(p), Cow::Borrowed(s)) => Cow::Borrowed(first_chars(s, p)),
                (Some(p), Cow::Owned(s)) => Cow::Owned(first_chars(&s, p).to_vec()),
                (None, s) => s,
            });
        }
        'f' | 'F' | 'e' | 'E' | 'g' | 'G' => {
            let v = as_float(arg, conversion)?;
            let body = float(conversion, spec, v.abs());
            format!("{}{}", sign(v.is_sign_negative() && !v.is_nan()), body)
        }
        other => return Err(FormatError::UnknownConversion(other)),
    };
    Ok(Cow::Owned(text.into_bytes()))
}

fn float(conversion: char, spec: &Spec, v: f64) -> String {
    if !v.is_finite() {
        let s = if v.is_nan() { "nan" } else { "inf" };
        return if conversion.is_ascii_uppercase() { s.to_uppercase() } else { s.to_string() };
    }
    let p = spec.precision.unwrap_or(6);
    let s = match conversion.to_ascii_lowercase() {
        'f' => format!("{v:.p$}"),
        'e' => exponential(v, p),
        _ => general(v, p, spec.alt),
    };
    if conversion.is_ascii_uppercase() { s.to_uppercase() } else { s }
}

/// C's `%e`: one digit, the fraction, and an exponent of at least two digits.
fn exponential(v: f64, p: usize) -> String {
    let s = format!("{v:.p$e}");
    let (mantissa, exponent) = s.split_once('e').expect("Rust writes an exponent");
    let exponent: i32 = exponent.parse().expect("an integer exponent");
    let mut out = String::from(mantissa);
    let _ = write!(out, "e{}{:02}", if exponent < 0 { '-' } else { '+' }, exponent.abs());
    out
}

/// C's `%g`: `%e` or `%f` by the exponent, trailing zeros removed.
fn general(v: f64, p: usize, alt: bool) -> String {
    let p = p.max(1);
    let e = exponential(v, p - 1);
    let exponent: i32 = e.split_once('e').map_or(0, |(_, x)| x.parse().unwrap_or(0));
    let s = if exponent < -4 || exponent >= p as i32 {
        e
    } else {
        let decimals = (p as i32 - 1 - exponent).max(0) as usize;
        format!("{v:.decimals$}")
    };
    if alt {
        return s;
    }
    match s.split_once('e') {
        Some((m, x)) => format!("{}e{x}", trim_fraction(m)),
        None => trim_fraction(&s).to_string(),
    }
}

fn trim_fraction(s: &str) -> &str {
    if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { s }
}

fn pad(out: &mut Out, spec: &Spec, body: &[u8], conversion: char) {
    let len = if spec.width > 0 { chars(body) } else { 0 };
    if len >= spec.width {
        out.push(body);
    } else if spec.left {
        out.push(body);
        out.repeat(b' ', spec.width - len);
    } else if spec.zero && !matches!(conversion, 's' | 'c') {
        // Zeros go after the sign.
        let (sign, digits) = body.split_at(body.iter().position(u8::is_ascii_alphanumeric).unwrap_or(0));
        out.push(sign);
        out.repeat(b'0', spec.width - len);
        out.push(digits);
    } else {
        out.repeat(b' ', spec.width - len);
        out.push(body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Arg::*;

    /// The whole text, checked to be kept whole.
    fn text(fmt: &str, args: &[Arg]) -> Result<String, FormatError> {
        let formatted = format(fmt.as_bytes(), args)?;
        assert_eq!(formatted.cut, 0);
        let text = String::from_utf8(formatted.text).unwrap();
        assert_eq!(formatted.chars, text.chars().count());
        Ok(text)
    }

    /// HMPL 3.2: the manual's examples.
    #[test]
    fn manual_examples() {
        let args = [Int(321), Float(1428.57), Str(b"hello world")];
        let rows = [
            ("var1: %d, var2: %f, str: %s", "var1: 321, var2: 1428.570000, str: hello world"),
            ("var1: %d, var2: %e, str: %s", "var1: 321, var2: 1.428570e+03, str: hello world"),
            ("var1: %d, var2: %g, str: %s", "var1: 321, var2: 1428.57, str: hello world"),
        ];
        for (fmt, expected) in rows {
            assert_eq!(text(fmt, &args).unwrap(), expected);
        }
        assert_eq!(
            text("%f %e %g", &[Float(589.0), Float(589.0), Float(589.0)]).unwrap(),
            "589.000000 5.890000e+02 589"
        );
    }

    #[test]
    fn c_conversions() {
        let rows: [(&str, Arg, &str); 15] = [
            ("%i", Int(-7), "-7"),
            ("%u", Int(-1), "4294967295"),
            ("%x", Int(255), "ff"),
            ("%08x", Int(0x8300_0078), "83000078"),
            ("%#x", Int(-1), "0xffffffff"),
            ("%c", Int(65), "A"),
            ("%5d|", Int(42), "   42|"),
            ("%-5d|", Int(42), "42   |"),
            ("%05d", Int(-42), "-0042"),
            ("%.2f", Float(1.23456), "1.23"),
            ("%g", Float(0.0001), "0.0001"),
            ("%g", Float(1e-5), "1e-05"),
            ("%g", Float(1234567.0), "1.23457e+06"),
            ("%.3s", Str(b"abcdef"), "abc"),
            ("%512d", Int(1), &format!("{:>512}", 1)),
        ];
        for (fmt, arg, expected) in rows {
            assert_eq!(text(fmt, &[arg]).unwrap(), expected, "{fmt}");
        }
        // Precision and width count characters.
        assert_eq!(text("%.2s|%4s|", &[Str("éèê".as_bytes()), Str("éèê".as_bytes())]).unwrap(), "éè| éèê|");
        assert_eq!(text("100%%", &[]).unwrap(), "100%");
    }

    #[test]
    fn too_few_arguments_is_an_error_and_extra_ones_are_ignored() {
        assert_eq!(format(b"%d %d", &[Int(1)]).unwrap_err(), FormatError::MissingArgument(1));
        assert_eq!(text("%d", &[Int(1), Int(2)]).unwrap(), "1");
    }

    /// HMPL 3.2: -1 on a bad format. Widths and precisions that C would take but no HMPL
    /// string can hold are bad formats, however large (they used to panic or abort).
    #[test]
    fn extreme_fields_are_bad_formats() {
        let rows = [
            "%.100000000f",
            "%99999999999999999999999999d",
            "%.99999999999g",
            "%300000000d",
            "%99999999999s",
            "%513d",
            "%-0+#.513e",
            "%*d",
            "%.*f",
        ];
        for fmt in rows {
            let error = format(fmt.as_bytes(), &[Float(1.5), Float(2.5)]).unwrap_err();
            assert!(matches!(error, FormatError::FieldTooWide | FormatError::UnknownConversion('*')), "{fmt}: {error}");
        }
    }

    /// Whatever a format asks for, one output line is kept and the rest only counted.
    #[test]
    fn the_text_is_kept_up_to_one_line_and_counted_whole() {
        let big = vec![b'x'; 10_000_000];
        let formatted = format(b"%s|%512d", &[Str(&big), Int(7)]).unwrap();
        assert_eq!(formatted.text.len(), MAX_LINE_BYTES);
        assert_eq!(formatted.chars, 10_000_000 + 1 + 512);
        assert_eq!(formatted.cut as usize, formatted.chars - MAX_LINE_BYTES);
        // Many wide fields: 2000 x 512 characters from a short format.
        let fmt = "%512d".repeat(2000);
        let args = vec![Int(1); 2000];
        let formatted = format(fmt.as_bytes(), &args).unwrap();
        assert_eq!((formatted.text.len(), formatted.chars), (MAX_LINE_BYTES, 2000 * 512));
    }

    #[test]
    fn bytes_that_are_no_utf8_pass_through_and_count_as_one_character() {
        let formatted = format(b"a\xff%s|%-3s|", &[Str(b"\xfe\xc3\xa9"), Str(b"\x80")]).unwrap();
        assert_eq!(formatted.text, b"a\xff\xfe\xc3\xa9|\x80  |");
        assert_eq!(formatted.chars, 9);
    }
}
