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
///
/// The double nearest the decimal `v` rounds to, exactly as printing with
/// `{:.9e}` and parsing back gives ([`round_exact`]), but by arithmetic in
/// the common case ([`Rounded`]).
pub fn round(v: f64) -> f64 {
    if !v.is_finite() {
        return v;
    }
    if v.abs() < ZERO {
        return 0.0;
    }
    match Rounded::new(v.abs()) {
        Some(r) => r.value().copysign(v),
        None => round_exact(v),
    }
}

/// The rounding by printing with `{:.9e}` and parsing back: exact, and slow
/// (about 0.2 µs, more than the rest of a number's JSON).
pub fn round_exact(v: f64) -> f64 {
    format!("{:.*e}", SIGNIFICANT - 1, v).parse().unwrap_or(v)
}

/// Powers of ten exact in a double (10^22 is the last one).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// `a > 0` rounded to ten significant digits: `a ≈ m × 10^(e - 9)` with
/// `10^9 <= m < 10^10`.
///
/// `q = a × 10^(9 - e)` is one correctly rounded product (or quotient) by an
/// exact power of ten, so it is within half an ulp of `q` (at most about 1e-6
/// below 10^10) of the exact scaled value; rounding `q` to an integer then
/// rounds `a` exactly unless `q`'s fraction lies within 1e-5 of one half.
/// There, and where the power of ten is not exact, `None`: the caller prints
/// exactly ([`round_exact`]).
struct Rounded {
    m: u64,
    e: i32,
}

impl Rounded {
    fn new(a: f64) -> Option<Rounded> {
        // floor(log10 a), possibly one too small: log10(2) × the binary exponent
        let bexp = ((a.to_bits() >> 52) & 0x7ff) as i32 - 1023;
        let mut e = (bexp * 78_913) >> 18;
        let mut q = Self::scale(a, 9 - e)?;
        if q >= 10_000_000_000.0 {
            e += 1;
            q = Self::scale(a, 9 - e)?;
        }
        // 0 < q < 10^10 + 1: truncation is exact and quick (no libm floor),
        // and one instruction through i64 (through u64 it takes a dozen).
        let whole = q as i64;
        let f = q - whole as f64;
        if (f - 0.5).abs() < 1e-5 {
            return None;
        }
        let mut m = whole as u64 + u64::from(f > 0.5);
        if m == 10_000_000_000 {
            // 9999999999.5 carried into an eleventh digit
            (m, e) = (1_000_000_000, e + 1);
        }
        if m < 1_000_000_000 {
            // log10 estimated one too large (cannot happen with the floor above)
            return None;
        }
        Some(Rounded { m, e })
    }

    /// `a × 10^k` in one correctly rounded operation, when `10^|k|` is exact.
    fn scale(a: f64, k: i32) -> Option<f64> {
        let p = POW10.get(k.unsigned_abs() as usize)?;
        Some(if k >= 0 { a * p } else { a / p })
    }

    /// The double nearest `m × 10^(e - 9)`: again one correctly rounded
    /// operation (m < 2^53, the power exact), or the exact rounding.
    fn value(&self) -> f64 {
        let k = self.e - 9;
        match POW10.get(k.unsigned_abs() as usize) {
            Some(p) if k >= 0 => self.m as f64 * p,
            Some(p) => self.m as f64 / p,
            None => round_exact(self.m as f64 * 10f64.powi(k)),
        }
    }
}

/// "00" to "99", two bytes each.
const PAIRS: &[u8; 200] = b"\
0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// `v` as serde_json prints the double [`round`] gives (`null` if not finite).
///
/// The shortest form of that double is the ten rounded digits with trailing
/// zeros dropped (a decimal of at most 15 digits is the shortest form of its
/// nearest double), laid out as zmij (serde_json's printer) lays them out for
/// exponents in its fixed notation (-5..=15); other exponents and undecided
/// roundings go through the rounded double and zmij.
pub fn push_json(out: &mut Vec<u8>, v: f64) {
    if !v.is_finite() {
        out.extend_from_slice(b"null");
        return;
    }
    if v.abs() < ZERO {
        out.extend_from_slice(b"0.0");
        return;
    }
    let fallback = |out: &mut Vec<u8>| {
        // Where the rounding overflows (near f64::MAX) the tree kept the number as it was.
        let x = round(v);
        let x = if x.is_finite() { x } else { v };
        out.extend_from_slice(zmij::Buffer::new().format_finite(x).as_bytes());
    };
    let Some(r) = Rounded::new(v.abs()).filter(|r| (-5..=15).contains(&r.e)) else {
        fallback(out);
        return;
    };
    // The ten digits two at a time (five look-ups instead of ten divisions).
    let mut digits = [b'0'; 2 * SIGNIFICANT];
    let (top, low) = ((r.m / 100_000_000) as usize, (r.m % 100_000_000) as u32);
    let (mid, bottom) = ((low / 10_000) as usize, (low % 10_000) as usize);
    for (k, pair) in [top, mid / 100, mid % 100, bottom / 100, bottom % 100]
        .into_iter()
        .enumerate()
    {
        digits[2 * k..2 * k + 2].copy_from_slice(&PAIRS[2 * pair..2 * pair + 2]);
    }
    // Trailing zeros, from the digits read as integers: the last '0' bytes
    // are the high bytes of the little-endian words that XOR to zero (the
    // first digit is never '0': m >= 10^9).
    let (head, tail) = digits.split_at(8);
    let head = u64::from_le_bytes(head.try_into().unwrap_or([0; 8])) ^ 0x3030_3030_3030_3030;
    let tail = u16::from_le_bytes([tail[0], tail[1]]) ^ 0x3030;
    let zeros = if tail != 0 {
        tail.leading_zeros() / 8
    } else {
        2 + head.leading_zeros() / 8
    };
    let len = SIGNIFICANT - zeros as usize;
    // Laid out in place, at the end of `out`, by copies of fixed length
    // (ten digits, sixteen zeros; what follows overwrites the excess), then
    // cut to its length. (Laid out in a buffer on the stack and copied,
    // the copy's wide loads waited on the narrower stores before them: a
    // quarter of a number's time.)
    const ZEROS: &[u8; 16] = b"0000000000000000";
    let start = out.len();
    out.resize(start + 48, 0);
    let buf = &mut out[start..start + 48];
    let mut n = usize::from(v < 0.0);
    buf[0] = b'-';
    let e = r.e;
    if len as i32 - 1 <= e {
        // 1234e7 -> 12340000000.0
        buf[n..n + SIGNIFICANT].copy_from_slice(&digits[..SIGNIFICANT]);
        n += len;
        buf[n..n + 16].copy_from_slice(ZEROS);
        n += (e + 1 - len as i32) as usize;
        buf[n..n + 2].copy_from_slice(b".0");
        n += 2;
    } else if e >= 0 {
        // 1234e-2 -> 12.34
        let k = e as usize + 1;
        buf[n..n + SIGNIFICANT].copy_from_slice(&digits[..SIGNIFICANT]);
        n += k;
        buf[n] = b'.';
        n += 1;
        buf[n..n + SIGNIFICANT].copy_from_slice(&digits[k..k + SIGNIFICANT]);
        n += len - k;
    } else {
        // 1234e-6 -> 0.001234
        buf[n..n + 2].copy_from_slice(b"0.");
        n += 2;
        buf[n..n + 16].copy_from_slice(ZEROS);
        n += (-e - 1) as usize;
        buf[n..n + SIGNIFICANT].copy_from_slice(&digits[..SIGNIFICANT]);
        n += len;
    }
    out.truncate(start + n);
}

/// Appends `src[..n]` to `out` by copying all of `src` (a fixed length) and
/// truncating: a copy of fixed length compiles to a few moves, one of
/// variable length to a call of `memcpy` (which cost a fifth of a number
/// when numbers were copied this way; the JSON's separators and indents
/// are now).
#[inline]
pub(crate) fn push_prefix<const N: usize>(out: &mut Vec<u8>, src: &[u8; N], n: usize) {
    let len = out.len();
    out.extend_from_slice(src);
    out.truncate(len + n.min(N));
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
    match fixed_fast(v, decimals) {
        Some(t) if t.len() >= width => t,
        Some(t) => format!("{t:>width$}"),
        None => format!("{v:>width$.decimals$}"),
    }
}

/// `format!("{v:.decimals$}")` by integer arithmetic where that is exact:
/// the table of a 500-case path has some 75 000 numbers, and the formatter's
/// exact float printing was the larger part of the tables' cost (with the
/// padding, two thirds of the solves').
///
/// `q = |v| × 10^d` is one correctly rounded product, within half an ulp
/// (below 2^40: at most 1.2e-4) of the exact scaled value, so rounding `q`
/// to an integer rounds `v` exactly as the formatter does (the nearest, from
/// the double's exact value) unless `q`'s fraction lies within 1e-3 of one
/// half. There, for large values or many decimals, and for a value that
/// rounds to zero (printed with its sign), `None`.
fn fixed_fast(v: f64, decimals: usize) -> Option<String> {
    let p = *POW10.get(decimals).filter(|_| decimals <= 9)?;
    let q = v.abs() * p;
    // Not a number or infinite: the formatter's `NaN` and `inf`.
    if q.is_nan() || q >= (1u64 << 40) as f64 {
        return None;
    }
    let whole = q as u64;
    let f = q - whole as f64;
    if (f - 0.5).abs() < 1e-3 {
        return None;
    }
    let n = whole + u64::from(f > 0.5);
    if n == 0 && v.is_sign_negative() {
        return None;
    }
    let unit = p as u64;
    let mut t = String::with_capacity(24);
    if v < 0.0 {
        t.push('-');
    }
    let _ = std::fmt::Write::write_fmt(&mut t, format_args!("{}", n / unit));
    if decimals > 0 {
        let frac = n % unit;
        t.push('.');
        let digits = frac.to_string();
        t.extend(std::iter::repeat_n('0', decimals - digits.len()));
        t.push_str(&digits);
    }
    Some(t)
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

    /// Ties, carries, tails at a half unit, the magnitudes solve prints, and a
    /// deterministic scatter over 1e-10..1e8 (xorshift).
    fn samples() -> Vec<f64> {
        let mut cases = vec![
            0.5,
            1.5,
            2.5,
            0.30000000000000004,
            1.00000000005,
            1.000000000049999,
            9.9999999995,
            9.99999999949,
            99999.999995,
            123456.78905,
            1e-10,
            -1e-10,
            1.0000000001e-10,
            765.9716796426885,
            4.5e15,
            1e22,
            1e23,
            1.7976931348623157e308,
            5e-324,
            -2.5e-7,
            12345678905.0,
            0.1 + 0.2,
            2000.0,
            -0.0,
            1e15,
            1.5e16,
            9.99999999996e15,
            0.00001234567891,
            0.000012345,
            99999.99999999,
        ];
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let mant = (x >> 11) as f64 / (1u64 << 53) as f64;
            let e = (x % 27) as i32 - 12;
            let sign = if x & 1 == 0 { 1.0 } else { -1.0 };
            cases.push(sign * mant * 10f64.powi(e));
            // values at a tenth-digit half unit, the hard case
            cases.push(sign * ((x >> 30) as f64 + 0.5) * 10f64.powi(e - 10));
        }
        cases
    }

    /// Table numbers are what Rust's formatter prints, on the scatter
    /// above, at every number of decimals the tables use and beyond.
    #[test]
    fn table_numbers_are_the_formatters() {
        let extra = [
            2.675,
            1.005,
            0.125,
            -0.125,
            0.0625,
            1e11 + 0.5,
            4.35,
            -7.5,
            f64::NAN,
            f64::INFINITY,
        ];
        for v in samples().into_iter().step_by(7).chain(extra) {
            for d in 0..=10 {
                let v = if v.abs() < 0.5 * 10f64.powi(-(d as i32)) {
                    0.0
                } else {
                    v
                };
                assert_eq!(
                    fixed(v, d, 0),
                    format!("{v:.d$}"),
                    "{v:e} with {d} decimals"
                );
                assert_eq!(
                    fixed(v, d, 12),
                    format!("{v:>12.d$}"),
                    "{v:e} with {d} decimals"
                );
            }
        }
    }

    #[test]
    fn the_fast_rounding_is_the_exact_one() {
        for v in samples() {
            let want = if v.abs() < ZERO { 0.0 } else { round_exact(v) };
            assert_eq!(round(v).to_bits(), want.to_bits(), "{v:e}");
        }
    }

    #[test]
    fn json_numbers_print_as_serde_json_prints_the_exact_rounding() {
        for v in samples() {
            // round_json keeps a number whose rounding overflows
            let want = match round_exact(v) {
                _ if v.abs() < ZERO => 0.0,
                r if r.is_finite() => r,
                _ => v,
            };
            let want = serde_json::to_string(&want).unwrap_or_default();
            let mut got = Vec::new();
            push_json(&mut got, v);
            let got = String::from_utf8(got).expect("ASCII");
            assert_eq!(got, want, "{v:e}");
        }
        let mut got = Vec::new();
        push_json(&mut got, f64::NAN);
        let got = String::from_utf8(got).expect("ASCII");
        assert_eq!(got, "null");
    }

    #[test]
    fn json_numbers_are_rounded_integers_kept() {
        let mut v = serde_json::json!({"a": [0.30000000000000004, 5], "b": {"c": -1e-13}});
        round_json(&mut v);
        assert_eq!(v.to_string(), r#"{"a":[0.3,5],"b":{"c":0.0}}"#);
    }
}
