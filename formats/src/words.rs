//! Numbers and counts as messages print them: `1 component`, `3 components`; a float
//! in the shortest form that reads back to within its sixth significant digit
//! (`0.074416`, not `0.07441600000000001`), never a negative zero.

/// `n` and its noun, singular for one: `count(1, "component", "components")`.
pub fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// `n components`, `1 component`.
pub fn components(n: usize) -> String {
    count(n, "component", "components")
}

/// `v` with six significant digits, trailing zeros dropped: plain decimals from 1e-3 to
/// 1e6 (`0.074416`, `12.5`, `4`), scientific notation outside (`2.6996e-4`); zero and any
/// value that rounds to zero at that precision is `0`, never `-0`; not-a-number and the
/// infinities as Rust writes them.
pub fn number(v: f64) -> String {
    if !v.is_finite() {
        return v.to_string();
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    let text = if (1e-3..1e6).contains(&a) {
        // Digits after the point for six significant ones; the rounding may carry into
        // one more integer digit (999999.5 → 1000000), which only drops a decimal.
        let decimals = (5 - a.log10().floor() as i32).max(0) as usize;
        trim_zeros(format!("{v:.decimals$}"))
    } else {
        let s = format!("{v:.5e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        format!("{}e{exponent}", trim_zeros(mantissa.to_string()))
    };
    if text.trim_start_matches('-').chars().all(|c| c == '0' || c == '.') {
        "0".into()
    } else {
        text
    }
}

/// `1.2500` → `1.25`, `4.000` → `4`; a number without a point is left alone.
fn trim_zeros(s: String) -> String {
    if !s.contains('.') {
        return s;
    }
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_singular_for_one() {
        assert_eq!(components(1), "1 component");
        assert_eq!(components(9), "9 components");
        assert_eq!(count(0, "face", "faces"), "0 faces");
    }

    #[test]
    fn numbers_are_short_and_never_negative_zero() {
        assert_eq!(number(0.07441600000000001), "0.074416");
        assert_eq!(number(2.0020000000000007), "2.002");
        assert_eq!(number(0.007315873340622664), "0.00731587");
        assert_eq!(number(4.0), "4");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(-1e-12), "-1e-12");
        assert_eq!(number(-0.25), "-0.25");
        assert_eq!(number(2.6996e-4), "2.6996e-4");
        assert_eq!(number(1234567.0), "1.23457e6");
        assert_eq!(number(999999.9), "1000000");
        assert_eq!(number(18683.904729), "18683.9");
        assert_eq!(number(f64::NAN), "NaN");
        // Read back, within the sixth significant digit.
        for v in [0.1 + 0.2, 1.0 / 3.0, -123.456789, 9.87654321e-7, 6.02e23] {
            let back: f64 = number(v).parse().unwrap();
            assert!(((back - v) / v).abs() < 1e-5, "{v} → {}", number(v));
        }
    }
}
