//! Number formatting for every output of `solve` and `kc`, so that precision is
//! decided once: JSON and CSV carry [`SIGNIFICANT`] significant digits (far below
//! the solver's tolerance, and stable under last-bit changes of the arithmetic),
//! tables a fixed number of decimals per quantity.

use serde_json::Value;

/// Significant digits of numbers in JSON and CSV output.
pub const SIGNIFICANT: usize = 10;

/// Magnitudes below this print as 0: solver noise (1e-10 mm, N, deg or N·mm is
/// far below anything measurable), which would otherwise make output flicker.
pub const ZERO: f64 = 1e-10;

/// `v` rounded to [`SIGNIFICANT`] digits (noise flushed to 0; `-0` becomes `0`).
pub fn round(v: f64) -> f64 {
    if !v.is_finite() {
        return v;
    }
    if v.abs() < ZERO {
        return 0.0;
    }
    // Printing then parsing gives the double nearest the rounded decimal, which
    // serde_json and `{}` then print in its shortest form.
    format!("{:.*e}", SIGNIFICANT - 1, v).parse().unwrap_or(v)
}

/// `v` for a CSV field: [`round`], shortest form.
pub fn csv(v: f64) -> String {
    format!("{}", round(v))
}

/// `v` with `decimals` decimals for a table column, right-aligned in `width`.
pub fn fixed(v: f64, decimals: usize, width: usize) -> String {
    let v = if v.abs() < 0.5 * 10f64.powi(-(decimals as i32)) {
        0.0
    } else {
        v
    };
    format!("{v:>width$.decimals$}")
}

/// Rounds every number of a JSON value in place (integers are left alone).
pub fn round_json(v: &mut Value) {
    match v {
        Value::Number(n) if n.is_f64() => {
            if let Some(x) = n
                .as_f64()
                .and_then(|x| serde_json::Number::from_f64(round(x)))
            {
                *n = x;
            }
        }
        Value::Array(a) => a.iter_mut().for_each(round_json),
        Value::Object(o) => o.values_mut().for_each(round_json),
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_is_short_and_stable() {
        assert_eq!(csv(0.1 + 0.2), "0.3");
        assert_eq!(csv(-1e-14), "0");
        assert_eq!(csv(765.9716796426885), "765.9716796");
        assert_eq!(round(1.0000000000000002), 1.0);
        assert_eq!(fixed(-0.00001, 3, 8), "   0.000");
        assert_eq!(fixed(12.3456, 2, 7), "  12.35");
    }

    #[test]
    fn json_numbers_are_rounded_integers_kept() {
        let mut v = serde_json::json!({"a": [0.30000000000000004, 5], "b": {"c": -1e-13}});
        round_json(&mut v);
        assert_eq!(v.to_string(), r#"{"a":[0.3,5],"b":{"c":0.0}}"#);
    }
}
