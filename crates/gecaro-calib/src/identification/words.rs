//! Numbers as the identification's sentences print them: lengths and angles
//! with four decimals of a millimetre or a degree, and two significant digits
//! with an exponent below what four decimals show (a noise-free fit's
//! residual σ of 1.8e-13 mm is not "0.0000 mm"); other sizes with four
//! significant digits.

/// Below this (millimetres or degrees), four decimals would print zero.
const SHOWN_BY_DECIMALS: f64 = 5e-5;

/// `value` (millimetres or degrees) in words.
fn in_words(value: f64) -> String {
    if value != 0.0 && value.abs() < SHOWN_BY_DECIMALS {
        format!("{value:.1e}")
    } else {
        format!("{value:.4}")
    }
}

/// A length in metres, in millimetres: `0.0123 mm`, `1.8e-13 mm`.
pub(super) fn millimetres(metres: f64) -> String {
    format!("{} mm", in_words(metres * 1e3))
}

/// An angle in radians, in degrees: `0.0040°`, `2.1e-12°`.
pub(super) fn degrees(radians: f64) -> String {
    format!("{}°", in_words(radians.to_degrees()))
}

/// Four significant digits, without an exponent for ordinary sizes.
pub(super) fn significant(value: f64) -> String {
    if (1e-3..1e6).contains(&value) {
        let digits = (3 - value.log10().floor() as i32).max(0) as usize;
        format!("{value:.digits$}")
    } else {
        format!("{value:.3e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_decimals_and_an_exponent_where_they_would_print_zero() {
        assert_eq!(millimetres(1.23e-5), "0.0123 mm");
        assert_eq!(millimetres(0.0), "0.0000 mm");
        assert_eq!(millimetres(1.8e-16), "1.8e-13 mm");
        assert_eq!(millimetres(4.9e-8), "4.9e-5 mm");
        assert_eq!(millimetres(6e-8), "0.0001 mm");
        assert_eq!(degrees(std::f64::consts::PI), "180.0000°");
        assert_eq!(degrees(3.7e-14_f64.to_radians()), "3.7e-14°");
    }
}
