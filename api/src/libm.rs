//! HMPL ch. 4 math as pure functions of numbers, shared by the Lua bindings and the Native
//! ASCII server: C's libm with the manual's overflow rule.

use crate::{Local, LocalCall};

/// HMPL 4.12-4.14: a result too large for a double is the largest double (with its sign),
/// where C gives HUGE_VAL; infinite inputs and poles stay infinite.
pub fn overflow_to_max(r: f64, finite_inputs: bool) -> f64 {
    if r.is_infinite() && finite_inputs { f64::MAX.copysign(r) } else { r }
}

/// HMPL 4.13.
pub fn exp(x: f64) -> f64 {
    overflow_to_max(x.exp(), x.is_finite())
}

/// HMPL 4.14.
pub fn pow(x: f64, y: f64) -> f64 {
    overflow_to_max(x.powf(y), x.is_finite() && y.is_finite() && x != 0.0)
}

/// C's `ldexp` with HMPL 4.12's overflow: the largest double.
pub fn ldexp(x: f64, y: i64) -> f64 {
    // 2^y in steps that cannot overflow on their own; past ±2200 the result is 0 or infinite.
    let y = y.clamp(-2200, 2200) as i32;
    let mut r = x;
    let mut left = y;
    while left != 0 {
        let step = left.clamp(-1000, 1000);
        r *= 2f64.powi(step);
        left -= step;
    }
    overflow_to_max(r, x.is_finite())
}

/// Whether `local` is one of ch. 4's functions.
pub fn is_math(local: Local) -> bool {
    matches!(
        local,
        Local::sin
            | Local::cos
            | Local::tan
            | Local::asin
            | Local::acos
            | Local::atan
            | Local::atan2
            | Local::abs
            | Local::fabs
            | Local::ceil
            | Local::floor
            | Local::ldexp
            | Local::exp
            | Local::pow
            | Local::log
            | Local::log10
            | Local::sqrt
            | Local::cbrt
            | Local::hypot
    )
}

/// The ch. 4 function `call` computes, `None` for a call of another function. `abs` is of
/// an integer, as a double: a front end words an `abs` that does not fit an integer itself.
pub fn evaluate<V>(call: &LocalCall<'_, V>) -> Option<f64> {
    Some(match *call {
        LocalCall::sin { x } => x.sin(),
        LocalCall::cos { x } => x.cos(),
        LocalCall::tan { x } => x.tan(),
        LocalCall::asin { x } => x.asin(),
        LocalCall::acos { x } => x.acos(),
        LocalCall::atan { x } => x.atan(),
        LocalCall::sqrt { x } => x.sqrt(),
        LocalCall::abs { x } => (x as f64).abs(),
        LocalCall::fabs { x } => x.abs(),
        LocalCall::ceil { x } => x.ceil(),
        LocalCall::floor { x } => x.floor(),
        LocalCall::exp { x } => exp(x),
        LocalCall::log { x } => x.ln(),
        LocalCall::log10 { x } => x.log10(),
        LocalCall::cbrt { x } => x.cbrt(),
        LocalCall::atan2 { y, x } => y.atan2(x),
        LocalCall::pow { x, y } => pow(x, y),
        LocalCall::hypot { x, y } => x.hypot(y),
        LocalCall::ldexp { x, y } => ldexp(x, y),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::call::{Value, from_values};

    /// HMPL ch. 4's printed results through `evaluate`.
    #[test]
    fn chapter_4_rows() {
        let rows: [(&str, LocalCall<()>, f64); 5] = [
            ("HMPL 4.14 pow(4.73, 12)", LocalCall::pow { x: 4.73, y: 12.0 }, 125_410_439.217_423),
            ("HMPL 4.7 atan2(10, -10) = 135 deg", LocalCall::atan2 { y: 10.0, x: -10.0 }, 135f64.to_radians()),
            ("HMPL 4.12 ldexp(0.95, 4)", LocalCall::ldexp { x: 0.95, y: 4 }, 15.2),
            ("HMPL 4.13 exp(5)", LocalCall::exp { x: 5.0 }, 148.413159),
            ("HMPL 4.19 hypot(3, 4)", LocalCall::hypot { x: 3.0, y: 4.0 }, 5.0),
        ];
        for (row, call, want) in rows {
            let got = evaluate(&call).unwrap();
            assert!((got - want).abs() <= 1e-6 * want.abs().max(1.0), "{row}: {got} != {want}");
        }
        let not_math: LocalCall<()> = LocalCall::StringLen { str: b"x"[..].into() };
        assert_eq!(evaluate(&not_math), None, "not a ch. 4 function");
        // Every ch. 4 function of the registry, and only those, is evaluated.
        let mut math = 0;
        for spec in crate::registry::all() {
            if let crate::Func::Local(local) = spec.func {
                let ch4 = spec.manual.starts_with("HMPL 4.");
                assert_eq!(is_math(local), ch4, "{}", spec.name);
                if ch4 {
                    math += 1;
                    let values: Vec<Value> = spec.args.iter().map(|_| Value::Int(1)).collect();
                    let call: LocalCall<Value> = from_values(local, &values).unwrap();
                    assert!(evaluate(&call).is_some(), "{}", spec.name);
                }
            }
        }
        assert_eq!(math, 19, "HMPL ch. 4 has 19 functions");
    }

    /// HMPL 4.12-4.14: overflow gives the largest double.
    #[test]
    fn overflow_gives_the_largest_double() {
        assert_eq!(ldexp(0.95, 4), 15.2);
        assert_eq!(ldexp(1.0, 2000), f64::MAX);
        assert_eq!(ldexp(-1.0, i64::MAX), -f64::MAX);
        assert_eq!(ldexp(1.0, i64::MIN), 0.0);
        assert_eq!(ldexp(f64::INFINITY, 1), f64::INFINITY);
        assert_eq!(overflow_to_max(1000f64.exp(), true), f64::MAX);
        assert_eq!(overflow_to_max((-10f64).powf(309.0), true), -f64::MAX);
    }
}
