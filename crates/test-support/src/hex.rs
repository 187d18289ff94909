//! Python's `float.hex()` strings: `[-]0xH.HHHp[+-]E`, meaning `0xH.HHH * 2^E`, plus `inf`,
//! `-inf` and `nan`. Every finite `f64` has one, and reading it back is exact: the mantissa's
//! hex digits are an integer `m` (at most 53 significant bits for what `float.hex()` writes) and
//! the value is `m * 2^(E - 4 k)` for `k` fraction digits, a product by a power of two done in
//! two steps so that subnormal results are not flushed by an intermediate underflow.

use nalgebra::DMatrix;

/// Parses one `float.hex()` string.
///
/// ```
/// use stance_test_support::hex::parse_hex;
/// assert_eq!(parse_hex("-0x1.8p+3"), -12.0);
/// assert_eq!(parse_hex("0x0.0p+0"), 0.0);
/// assert_eq!(parse_hex("0x0.0000000000001p-1022"), f64::from_bits(1));
/// assert_eq!(parse_hex("-inf"), f64::NEG_INFINITY);
/// ```
///
/// # Panics
///
/// On anything else (the fixture is broken).
pub fn parse_hex(s: &str) -> f64 {
    let (neg, rest) = s.strip_prefix('-').map_or((false, s), |r| (true, r));
    let magnitude = match rest {
        "inf" => f64::INFINITY,
        "nan" => f64::NAN,
        _ => {
            let rest = rest
                .strip_prefix("0x")
                .unwrap_or_else(|| panic!("hex float expected, got {s:?}"));
            let (mant, exp) = rest
                .split_once('p')
                .unwrap_or_else(|| panic!("no exponent in {s:?}"));
            let exp: i32 = exp
                .parse()
                .unwrap_or_else(|_| panic!("bad exponent in {s:?}"));
            let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
            let mut m = u64::from_str_radix(int, 16)
                .unwrap_or_else(|_| panic!("bad integer part in {s:?}"));
            for c in frac.chars() {
                let d = c
                    .to_digit(16)
                    .unwrap_or_else(|| panic!("bad hex digit in {s:?}"));
                m = m
                    .checked_mul(16)
                    .and_then(|m| m.checked_add(u64::from(d)))
                    .unwrap_or_else(|| panic!("mantissa too long in {s:?}"));
            }
            let e = exp - 4 * frac.len() as i32;
            // Two exact steps: 2^e alone would underflow to 0 below 2^-1074.
            let half = e / 2;
            (m as f64) * 2f64.powi(half) * 2f64.powi(e - half)
        }
    };
    if neg {
        -magnitude
    } else {
        magnitude
    }
}

/// A matrix of `cols` columns from a JSON array of rows of `float.hex()` strings.
///
/// ```
/// let v = serde_json::json!([["0x1.0p+0", "-0x1.0p-1"]]);
/// let m = stance_test_support::hex::matrix(&v, 2);
/// assert_eq!((m[(0, 0)], m[(0, 1)]), (1.0, -0.5));
/// ```
pub fn matrix(rows: &serde_json::Value, cols: usize) -> DMatrix<f64> {
    let rows = rows.as_array().expect("an array of rows");
    DMatrix::from_fn(rows.len(), cols, |i, j| {
        parse_hex(rows[i][j].as_str().expect("a hex float string"))
    })
}
