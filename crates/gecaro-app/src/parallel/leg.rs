//! A measuring leg as a request states it: `leg_base` and `leg_platform`,
//! its sockets' centres as points with their units (`250mm,-100mm,0`, bare
//! numbers metres; the base's in the base frame, the platform's in the
//! platform frame), and `leg_gain` (metres of length per unit of reading:
//! 1 by default, a reading in the data's length unit being a length). Its
//! length at reading 0 is found from the data.

use gecaro_calib::parallel_robots::{MeasuringLeg, PlatformMeasure};

use crate::error::AppError;

/// The measuring leg the `leg` method needs (`None` for the others, which
/// refuse a leg stated), its length 0 until the data set it.
///
/// # Errors
/// The `leg` method without both sockets, a socket that is no point, a gain
/// no sensor has, a leg stated for another method.
pub(super) fn measuring_leg(
    measure: PlatformMeasure,
    base: Option<&str>,
    platform: Option<&str>,
    gain: Option<f64>,
) -> Result<Option<MeasuringLeg>, AppError> {
    if measure != PlatformMeasure::Leg {
        if base.is_some() || platform.is_some() || gain.is_some() {
            return Err(AppError::setting(
                if base.is_some() {
                    "leg_base"
                } else if platform.is_some() {
                    "leg_platform"
                } else {
                    "leg_gain"
                },
                format!(
                    "states a measuring leg, which only the `leg` method reads (not `{}`)",
                    measure.name()
                ),
            ));
        }
        return Ok(None);
    }
    let point = |text: Option<&str>, key: &str, what: &str| {
        let text = text.ok_or_else(|| {
            AppError::setting(
                key,
                format!(
                    "the `leg` method needs the measuring leg's {what} socket: its centre with \
                     its units (250mm,-100mm,0)"
                ),
            )
        })?;
        gecaro_io::parse_point(text, &format!("the leg's {what} socket"))
            .map_err(|message| AppError::setting(key, message))
    };
    let base = point(base, "leg_base", "base")?;
    let platform = point(platform, "leg_platform", "platform")?;
    Ok(Some(MeasuringLeg::new(
        base,
        platform,
        gain.unwrap_or(1.0),
    )?))
}
