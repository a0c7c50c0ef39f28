//! HMPL ch. 3's string functions that compute a value from their strings alone, as pure
//! functions shared by the Lua bindings and the Native ASCII server. A string is read as
//! C reads it: up to its first NUL byte (`c_str`).

use crate::Local;

/// The string as C sees it: up to its first NUL byte.
pub fn c_str(s: &[u8]) -> &[u8] {
    &s[..s.iter().position(|&b| b == 0).unwrap_or(s.len())]
}

/// Whether `local` is one of the functions of this module (the others of ch. 3 give a
/// string or change memory: they are a script's).
pub fn is_pure(local: Local) -> bool {
    matches!(
        local,
        Local::StringLen | Local::IsStringEqual | Local::StrFindCharEx | Local::StrFindStr | Local::StringToDouble
    )
}

/// HMPL 3.4 `StringLen`: the length without the terminator.
pub fn len(s: &[u8]) -> i64 {
    c_str(s).len() as i64
}

/// HMPL 3.5 `IsStringEqual`.
pub fn equal(a: &[u8], b: &[u8]) -> bool {
    c_str(a) == c_str(b)
}

/// HMPL 3.7 `StrFindCharEx`: the offset of the first character of `s` in `set`
/// (`complement` false) or not in it (true), -1 when there is none.
pub fn find_char_ex(s: &[u8], set: &[u8], complement: bool) -> i64 {
    let set = c_str(set);
    offset(c_str(s).iter().position(|b| set.contains(b) != complement))
}

/// HMPL 3.8 `StrFindStr`: the offset of the first `sub` in `s` (0 for an empty `sub`, as
/// C's `strstr`), -1 when there is none.
pub fn find_str(s: &[u8], sub: &[u8]) -> i64 {
    let (s, sub) = (c_str(s), c_str(sub));
    offset(if sub.is_empty() { Some(0) } else { s.windows(sub.len()).position(|w| w == sub) })
}

/// An offset as HMPL gives it: -1 for none.
pub fn offset(found: Option<usize>) -> i64 {
    found.map_or(-1, |i| i as i64)
}

/// HMPL 3.13 `StringToDouble`, C's `atof`: leading white space, then the longest prefix
/// that is a decimal number (sign, digits, point, exponent) or `inf`, `infinity`, `nan`;
/// 0 when there is none.
pub fn to_double(s: &[u8]) -> f64 {
    let s = c_str(s);
    let s = &s[s.iter().position(|b| !b" \t\n\x0B\x0C\r".contains(b)).unwrap_or(s.len())..];
    let (sign, body) = match s.first() {
        Some(b'-') => (-1.0, &s[1..]),
        Some(b'+') => (1.0, &s[1..]),
        _ => (1.0, s),
    };
    let lower: Vec<u8> = body.iter().take(8).map(u8::to_ascii_lowercase).collect();
    if lower.starts_with(b"inf") {
        return sign * f64::INFINITY;
    }
    if lower.starts_with(b"nan") {
        return f64::NAN;
    }
    let digits = |from: usize| body[from..].iter().take_while(|b| b.is_ascii_digit()).count();
    let mut end = digits(0);
    let mut mantissa = end;
    if body.get(end) == Some(&b'.') {
        let fraction = digits(end + 1);
        mantissa += fraction;
        end += 1 + fraction;
    }
    if mantissa == 0 {
        return 0.0;
    }
    if matches!(body.get(end), Some(b'e' | b'E')) {
        let sign_len = usize::from(matches!(body.get(end + 1), Some(b'+' | b'-')));
        let exponent = digits(end + 1 + sign_len);
        if exponent > 0 {
            end += 1 + sign_len + exponent;
        }
    }
    // Only ASCII digits, point, sign and e: valid UTF-8 and a valid Rust float.
    std::str::from_utf8(&body[..end]).ok().and_then(|t| t.parse::<f64>().ok()).map_or(0.0, |v| sign * v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL 3.13 and C's `atof` on what follows the number.
    #[test]
    fn to_double_reads_as_atof() {
        for (text, want) in [
            ("1.234", 1.234),
            ("  -12.5e2xyz", -1250.0),
            ("0.05", 0.05),
            (".5", 0.5),
            ("5.", 5.0),
            ("1e", 1.0),
            ("abc", 0.0),
            ("", 0.0),
            ("-", 0.0),
            ("+3", 3.0),
            ("1e400", f64::INFINITY),
            ("2.5\0junk 9", 2.5),
        ] {
            assert_eq!(to_double(text.as_bytes()), want, "{text:?}");
        }
        assert_eq!(to_double(b"-Infinity"), f64::NEG_INFINITY);
        assert!(to_double(b"nan").is_nan());
    }

    /// The manual's examples of HMPL 3.4-3.8, and C's reading up to the first NUL.
    #[test]
    fn the_manuals_examples() {
        assert_eq!(len(b"hello world"), 11);
        assert_eq!(len(b"ab\0cd"), 2);
        assert!(equal(b"abc", b"abc\0x") && !equal(b"abc", b"abd"));
        assert_eq!(find_char_ex(b"hello world", b"ol", false), 2);
        assert_eq!(find_char_ex(b"hello world", b"helo", true), 5);
        assert_eq!(find_char_ex(b"abc", b"xyz", false), -1);
        assert_eq!(find_str(b"hello world", b"world"), 6);
        assert_eq!(find_str(b"hello", b""), 0);
        assert_eq!(find_str(b"hi", b"hello"), -1);
    }
}
