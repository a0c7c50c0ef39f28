//! The printf subset of HMPL's `Print`, `StringPrint` and `SendMsgEvent` (HMPL ch. 3):
//! `%d %i %u %x %c %s %f %e %g %%`, with C's flags, width and precision.

use std::fmt::Write;

/// One argument, as a script passed it.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg {
    Int(i64),
    Float(f64),
    Str(String),
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

/// Formats like C's `sprintf`. Extra arguments are ignored, as the manual says.
pub fn format(fmt: &str, args: &[Arg]) -> Result<String, FormatError> {
    let mut out = String::new();
    let mut next = args.iter();
    let mut chars = fmt.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        let mut spec = Spec::default();
        while let Some(&f) = chars.peek() {
            match f {
                '-' => spec.left = true,
                '+' => spec.plus = true,
                ' ' => spec.space = true,
                '#' => spec.alt = true,
                '0' => spec.zero = true,
                _ => break,
            }
            chars.next();
        }
        spec.width = digits(&mut chars).unwrap_or(0);
        if chars.peek() == Some(&'.') {
            chars.next();
            spec.precision = Some(digits(&mut chars).unwrap_or(0));
        }
        // Length modifiers (h, l, ll) change nothing for Lua's 64-bit numbers.
        while matches!(chars.peek(), Some('h' | 'l')) {
            chars.next();
        }
        let conversion = chars.next().ok_or(FormatError::Truncated)?;
        if conversion == '%' {
            out.push('%');
            continue;
        }
        let arg = next.next().ok_or(FormatError::MissingArgument(args.len()))?;
        let body = convert(conversion, &spec, arg)?;
        pad(&mut out, &spec, body, conversion);
    }
    Ok(out)
}

fn digits(chars: &mut std::iter::Peekable<std::str::Chars>) -> Option<usize> {
    let mut n = None;
    while let Some(d) = chars.peek().and_then(|c| c.to_digit(10)) {
        n = Some(n.unwrap_or(0) * 10 + d as usize);
        chars.next();
    }
    n
}

fn as_int(arg: &Arg, conversion: char) -> Result<i64, FormatError> {
    match arg {
        Arg::Int(i) => Ok(*i),
        Arg::Float(f) => Ok(f.trunc() as i64),
        Arg::Str(s) => s.trim().parse().map_err(|_| FormatError::NotANumber(conversion)),
    }
}

fn as_float(arg: &Arg, conversion: char) -> Result<f64, FormatError> {
    match arg {
        Arg::Int(i) => Ok(*i as f64),
        Arg::Float(f) => Ok(*f),
        Arg::Str(s) => s.trim().parse().map_err(|_| FormatError::NotANumber(conversion)),
    }
}

/// The bits a 64-bit C target prints for `%u`/`%x`: an `int` that fits is taken as 32 bits.
fn as_unsigned(v: i64) -> u64 {
    if (i32::MIN as i64..0).contains(&v) { v as u32 as u64 } else { v as u64 }
}

fn convert(conversion: char, spec: &Spec, arg: &Arg) -> Result<String, FormatError> {
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
    Ok(match conversion {
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
            let s = match arg {
                Arg::Str(s) => s.clone(),
                Arg::Int(i) => i.to_string(),
                Arg::Float(f) => f.to_string(),
            };
            match spec.precision {
                Some(p) => s.chars().take(p).collect(),
                None => s,
            }
        }
        'f' | 'F' | 'e' | 'E' | 'g' | 'G' => {
            let v = as_float(arg, conversion)?;
            let body = float(conversion, spec, v.abs());
            format!("{}{}", sign(v.is_sign_negative() && !v.is_nan()), body)
        }
        other => return Err(FormatError::UnknownConversion(other)),
    })
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

fn pad(out: &mut String, spec: &Spec, body: String, conversion: char) {
    let len = body.chars().count();
    if len >= spec.width {
        out.push_str(&body);
    } else if spec.left {
        out.push_str(&body);
        out.extend(std::iter::repeat_n(' ', spec.width - len));
    } else if spec.zero && !matches!(conversion, 's' | 'c') {
        // Zeros go after the sign.
        let (sign, digits) = body.split_at(body.find(|c: char| c.is_ascii_alphanumeric()).unwrap_or(0));
        out.push_str(sign);
        out.extend(std::iter::repeat_n('0', spec.width - len));
        out.push_str(digits);
    } else {
        out.extend(std::iter::repeat_n(' ', spec.width - len));
        out.push_str(&body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Arg::*;

    /// HMPL 3.2 and spec fact 16: the manual's examples.
    #[test]
    fn manual_examples() {
        let args = [Int(321), Float(1428.57), Str("hello world".into())];
        let rows = [
            ("var1: %d, var2: %f, str: %s", "var1: 321, var2: 1428.570000, str: hello world"),
            ("var1: %d, var2: %e, str: %s", "var1: 321, var2: 1.428570e+03, str: hello world"),
            ("var1: %d, var2: %g, str: %s", "var1: 321, var2: 1428.57, str: hello world"),
        ];
        for (fmt, expected) in rows {
            assert_eq!(format(fmt, &args).unwrap(), expected);
        }
        assert_eq!(
            format("%f %e %g", &[Float(589.0), Float(589.0), Float(589.0)]).unwrap(),
            "589.000000 5.890000e+02 589"
        );
    }

    #[test]
    fn c_conversions() {
        let rows: [(&str, Arg, &str); 14] = [
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
            ("%.3s", Str("abcdef".into()), "abc"),
        ];
        for (fmt, arg, expected) in rows {
            assert_eq!(format(fmt, &[arg]).unwrap(), expected, "{fmt}");
        }
        assert_eq!(format("100%%", &[]).unwrap(), "100%");
    }

    #[test]
    fn too_few_arguments_is_an_error_and_extra_ones_are_ignored() {
        assert_eq!(format("%d %d", &[Int(1)]), Err(FormatError::MissingArgument(1)));
        assert_eq!(format("%d", &[Int(1), Int(2)]).unwrap(), "1");
    }
}
