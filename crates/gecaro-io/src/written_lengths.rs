//! Lengths as people write them in an option or a study (`120mm`, `0.1`,
//! `-32.3mm`): a number, then its unit. The one table of the units written
//! beside a number (m, mm, um, rad, deg, %). A leaf: it imports nothing of
//! the crate, so that every reader of such text (payloads, tool poses,
//! priors, work regions) may use it.

/// What a number written with its unit measures.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Length,
    Angle,
    Gain,
}

/// The units a person writes beside a number, what each measures and its
/// factor to gecaro's units (m, rad, fraction): the one table of priors,
/// work regions and written lengths.
pub(crate) fn written_unit(unit: &str) -> Option<(Kind, f64)> {
    Some(match unit {
        "m" => (Kind::Length, 1.0),
        "mm" => (Kind::Length, 1e-3),
        "um" | "µm" => (Kind::Length, 1e-6),
        "rad" => (Kind::Angle, 1.0),
        "deg" | "°" => (Kind::Angle, std::f64::consts::PI / 180.0),
        "%" => (Kind::Gain, 0.01),
        _ => return None,
    })
}

/// The length of the number that starts `text`: sign, digits, decimals and
/// an exponent (`1e-3mm` is 1e-3 millimetres, not 1 of the unit `e-3mm`).
pub(crate) fn number_length(text: &str) -> usize {
    let bytes = text.as_bytes();
    let digits = |mut at: usize| {
        while at < bytes.len() && bytes[at].is_ascii_digit() {
            at += 1;
        }
        at
    };
    let mut end = usize::from(matches!(bytes.first(), Some(b'+' | b'-')));
    end = digits(end);
    if bytes.get(end) == Some(&b'.') {
        end = digits(end + 1);
    }
    if matches!(bytes.get(end), Some(b'e' | b'E')) {
        let mut exponent = end + 1;
        if matches!(bytes.get(exponent), Some(b'+' | b'-')) {
            exponent += 1;
        }
        let after = digits(exponent);
        if after > exponent {
            end = after;
        }
    }
    end
}

/// A length as a person writes it: a number with `m`, `mm` or `um` (`µm`),
/// metres when bare; and whether its unit was given. `what` names it in
/// messages.
pub(crate) fn length(text: &str, what: &str) -> Result<(f64, bool), String> {
    let (number, unit) = text.split_at(number_length(text));
    let unit = unit.trim();
    let factor = match (unit, written_unit(unit)) {
        ("", _) => 1.0,
        (_, Some((Kind::Length, factor))) => factor,
        (other, _) => {
            return Err(format!(
                "unknown length unit '{other}' in {what} '{text}' (m, mm, um)"
            ));
        }
    };
    let value = number
        .parse::<f64>()
        .map_err(|_| format!("{what} holds '{text}', not a length"))?
        * factor;
    if !value.is_finite() || value.abs() > gecaro_core::MAX_MAGNITUDE {
        return Err(format!("{what} holds '{text}', not a length in a cell"));
    }
    Ok((value, !unit.is_empty()))
}

/// A point's coordinates (or any lengths written together, a cube's centre
/// and side) as a person writes them (see [`length`]):
/// a bare number beside a coordinate that carries its unit is refused
/// (`-32.3,17.3,-17.3mm` would read the first two as metres); only a bare
/// 0, being 0 in any unit, may stand there.
pub(crate) fn point<const N: usize>(
    coordinates: &[&str; N],
    what: &str,
) -> Result<[f64; N], String> {
    let mut values = [0.0; N];
    let mut bare = None;
    let mut with_unit = None;
    for (value, coordinate) in values.iter_mut().zip(coordinates) {
        let (length, unit_given) = length(coordinate, what)?;
        *value = length;
        if unit_given {
            with_unit = Some(*coordinate);
        } else if length != 0.0 && bare.is_none() {
            bare = Some(*coordinate);
        }
    }
    if let (Some(bare), Some(with_unit)) = (bare, with_unit) {
        return Err(format!(
            "{what} '{}' mixes units: '{bare}' has none beside '{with_unit}'; give every \
             coordinate its unit ({bare}mm or {bare}m)",
            coordinates.join(",")
        ));
    }
    Ok(values)
}
