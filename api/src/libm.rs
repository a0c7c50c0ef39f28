//! HMPL ch. 4 math as pure functions of numbers, shared by the Lua bindings and the Native
//! ASCII server: C's libm with the manual's overflow rule.

use crate::Local;

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

/// The ch. 4 function `local` of `args`; `None` for another function or another number of
/// arguments. `abs` and `ldexp`'s exponent take integers: the caller checks they are.
pub fn evaluate(local: Local, args: &[f64]) -> Option<f64> {
    let one = |f: fn(f64) -> f64| match args {
        [x] => Some(f(*x)),
        _ => None,
    };
    let two = |f: fn(f64, f64) -> f64| match args {
        [x, y] => Some(f(*x, *y)),
        _ => None,
    };
    match local {
        Local::sin => one(f64::sin),
        Local::cos => one(f64::cos),
        Local::tan => one(f64::tan),
        Local::asin => one(f64::asin),
        Local::acos => one(f64::acos),
        Local::atan => one(f64::atan),
        Local::sqrt => one(f64::sqrt),
        Local::abs | Local::fabs => one(f64::abs),
        Local::ceil => one(f64::ceil),
        Local::floor => one(f64::floor),
        Local::exp => one(exp),
        Local::log => one(f64::ln),
        Local::log10 => one(f64::log10),
        Local::cbrt => one(f64::cbrt),
        Local::atan2 => two(f64::atan2),
        Local::pow => two(pow),
        Local::hypot => two(f64::hypot),
        Local::ldexp => two(|x, y| ldexp(x, y as i64)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// HMPL ch. 4's printed results through `evaluate`.
    #[test]
    fn chapter_4_rows() {
        let rows: [(&str, Local, &[f64], f64); 5] = [
            ("HMPL 4.14 pow(4.73, 12)", Local::pow, &[4.73, 12.0], 125_410_439.217_423),
            ("HMPL 4.7 atan2(10, -10) = 135 deg", Local::atan2, &[10.0, -10.0], 135f64.to_radians()),
            ("HMPL 4.12 ldexp(0.95, 4)", Local::ldexp, &[0.95, 4.0], 15.2),
            ("HMPL 4.13 exp(5)", Local::exp, &[5.0], 148.413159),
            ("HMPL 4.19 hypot(3, 4)", Local::hypot, &[3.0, 4.0], 5.0),
        ];
        for (row, local, args, want) in rows {
            let got = evaluate(local, args).unwrap();
            assert!((got - want).abs() <= 1e-6 * want.abs().max(1.0), "{row}: {got} != {want}");
        }
        assert_eq!(evaluate(Local::sin, &[1.0, 2.0]), None, "two arguments to sin");
        assert_eq!(evaluate(Local::StringLen, &[1.0]), None, "not a ch. 4 function");
        // Every ch. 4 function of the registry, and only those, is evaluated.
        let mut math = 0;
        for spec in crate::registry::all() {
            if let crate::Func::Local(local) = spec.func {
                let ch4 = spec.manual.starts_with("HMPL 4.");
                assert_eq!(is_math(local), ch4, "{}", spec.name);
                if ch4 {
                    math += 1;
                    assert!(evaluate(local, &vec![0.5; spec.args.len()]).is_some(), "{}", spec.name);
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
