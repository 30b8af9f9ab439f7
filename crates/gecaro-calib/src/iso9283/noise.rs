//! The noise σ of revisited poses: what a calibration's verdict tests its
//! residuals against, measured rather than stated.
//!
//! Each pose g revisited n_g times (positions `x_gj`, metres) scatters
//! about its barycentre by the robot's repeatability and the instrument's
//! noise together — what a calibration's residuals hold beyond the model's
//! error. Their pooled standard deviation per axis,
//!
//! `σ̂² = Σ_g Σ_j ‖x_gj − x̄_g‖² / (3 (N − G))`,
//!
//! with `N = Σ n_g` positions and `G` poses, is unbiased for isotropic
//! noise (each pose spends three degrees of freedom on its barycentre).
//! For Gaussian noise RP_l ≈ 3.615 σ (clause 7.2.2; the χ(3)
//! distribution's mean plus three standard deviations).

use nalgebra::Vector3;

use crate::Error;

/// A pooled σ and what it rests on.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PooledNoise {
    /// σ̂ per axis (m).
    pub sigma: f64,
    /// Poses revisited (G).
    pub poses: usize,
    /// Positions (N).
    pub positions: usize,
    /// The largest RP_l of the poses (m).
    pub repeatability: f64,
}

/// The pooled σ of `groups`, each a pose's revisited positions (module
/// docs).
///
/// # Errors
/// [`Error::InvalidData`] for a pose visited once, no pose, or a position
/// that is not finite.
pub fn pooled_noise(groups: &[Vec<Vector3<f64>>]) -> Result<PooledNoise, Error> {
    let invalid = |message: String| Error::InvalidData {
        line: None,
        message,
    };
    if groups.is_empty() {
        return Err(invalid("no revisited pose".into()));
    }
    let mut squares = 0.0;
    let mut positions = 0;
    let mut repeatability: f64 = 0.0;
    for (index, group) in groups.iter().enumerate() {
        if group.len() < 2 {
            return Err(invalid(format!(
                "pose {} is visited {} time(s); a repeatability needs 2 visits or more",
                index + 1,
                group.len()
            )));
        }
        if group.iter().any(|x| !x.iter().all(|v| v.is_finite())) {
            return Err(invalid(format!(
                "pose {}: a position is not finite",
                index + 1
            )));
        }
        let barycentre = group.iter().sum::<Vector3<f64>>() / group.len() as f64;
        let distances: Vec<f64> = group.iter().map(|x| (x - barycentre).norm()).collect();
        squares += distances.iter().map(|d| d * d).sum::<f64>();
        positions += group.len();
        let n = distances.len() as f64;
        let mean = distances.iter().sum::<f64>() / n;
        let deviation =
            (distances.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        repeatability = repeatability.max(mean + 3.0 * deviation);
    }
    let freedom = 3 * (positions - groups.len());
    Ok(PooledNoise {
        sigma: (squares / freedom as f64).sqrt(),
        poses: groups.len(),
        positions,
        repeatability,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::Sampler;

    /// Simulated truth: 20 poses × 30 visits with Gaussian noise σ per axis
    /// give σ̂ within 3 % of σ and RP_l near 3.615 σ; a pose visited once
    /// is refused.
    #[test]
    fn the_pooled_sigma_finds_the_simulated_noise() {
        let mut sampler = Sampler::new(78);
        let sigma = 2e-5;
        let groups: Vec<Vec<Vector3<f64>>> = (0..20)
            .map(|g| {
                let centre = Vector3::new(g as f64 * 0.1, 0.5, 0.3);
                (0..30)
                    .map(|_| centre + sampler.gaussian_vector(sigma))
                    .collect()
            })
            .collect();
        let pooled = pooled_noise(&groups).expect("pooled");
        assert!(
            (pooled.sigma / sigma - 1.0).abs() < 0.03,
            "{}",
            pooled.sigma
        );
        assert_eq!((pooled.poses, pooled.positions), (20, 600));
        assert!(pooled.repeatability > 3.0 * sigma && pooled.repeatability < 5.0 * sigma);
        let once = vec![vec![Vector3::zeros()]];
        assert!(pooled_noise(&once).is_err());
        assert!(pooled_noise(&[]).is_err());
    }
}
