//! ISO 9283's test cube as a person states it: `auto`, or its centre and
//! side `CX,CY,CZ,SIDE` with their units (`800mm,0,600mm,400mm`; metres when
//! every number is bare; a bare number beside one with a unit refused).

/// The cube stated by `text`: `None` for `auto`, else its centre (m, the
/// robot's world frame) and side (m).
///
/// ```
/// let (centre, side) = gecaro_io::parse_test_cube("800mm,0,600mm,400mm").unwrap().unwrap();
/// assert_eq!((centre[0], side), (0.8, 0.4));
/// assert!(gecaro_io::parse_test_cube("auto").unwrap().is_none());
/// assert!(gecaro_io::parse_test_cube("800,0,600mm,400mm").is_err());
/// ```
///
/// # Errors
/// A sentence naming what is wrong: the count, a unit, a mix of bare
/// numbers and units, a side that is not above 0.
pub fn parse_test_cube(text: &str) -> Result<Option<([f64; 3], f64)>, String> {
    let text = text.trim();
    if text.eq_ignore_ascii_case("auto") {
        return Ok(None);
    }
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    let Ok(parts) = <[&str; 4]>::try_from(parts.as_slice()) else {
        return Err(format!(
            "'{text}' is not a test cube: `auto`, or its centre and side with units, \
             CX,CY,CZ,SIDE (800mm,0,600mm,400mm)"
        ));
    };
    let [x, y, z, side] = crate::written_lengths::point(&parts, "the test cube")?;
    if side <= 0.0 {
        return Err(format!(
            "the test cube '{text}' has a side of {side} m; it needs one above 0"
        ));
    }
    Ok(Some(([x, y, z], side)))
}
