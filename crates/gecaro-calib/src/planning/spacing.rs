//! The minimum joint-space distance between chosen units.

use std::collections::HashMap;

use nalgebra::DVector;

/// Which candidate units lie closer than the minimum distance to a chosen
/// (or kept) one. The distance of two units is the smallest Euclidean norm
/// of the difference of their joint variables (radians and metres), over
/// their configurations.
pub(super) struct Spacing {
    /// Joint variables of every configuration of every candidate unit.
    configurations: Vec<Vec<DVector<f64>>>,
    distance: f64,
    /// How many chosen or kept units lie within `distance` of each unit.
    blocked: Vec<u32>,
    /// The units within `distance` of a unit, once computed.
    neighbours: HashMap<usize, Vec<usize>>,
}

impl Spacing {
    /// No constraint when `distance` is zero.
    pub(super) fn new(configurations: Vec<Vec<DVector<f64>>>, distance: f64) -> Self {
        Spacing {
            blocked: vec![0; configurations.len()],
            configurations,
            distance,
            neighbours: HashMap::new(),
        }
    }

    fn active(&self) -> bool {
        self.distance > 0.0
    }

    /// Whether a minimum distance is asked.
    pub(super) fn is_active(&self) -> bool {
        self.active()
    }

    fn near(&self, a: &[DVector<f64>], b: &[DVector<f64>]) -> bool {
        a.iter()
            .any(|p| b.iter().any(|q| (p - q).norm() < self.distance))
    }

    /// Blocks, for good, every unit near one of `configurations` (a kept unit).
    pub(super) fn keep(&mut self, configurations: &[DVector<f64>]) {
        if !self.active() {
            return;
        }
        for unit in 0..self.configurations.len() {
            if self.near(&self.configurations[unit], configurations) {
                self.blocked[unit] += 1;
            }
        }
    }

    /// Records that unit `s` was chosen (`added`) or dropped.
    pub(super) fn place(&mut self, s: usize, added: bool) {
        if !self.active() {
            return;
        }
        let neighbours = match self.neighbours.remove(&s) {
            Some(neighbours) => neighbours,
            None => (0..self.configurations.len())
                .filter(|unit| self.near(&self.configurations[*unit], &self.configurations[s]))
                .collect(),
        };
        for unit in &neighbours {
            if added {
                self.blocked[*unit] += 1;
            } else {
                self.blocked[*unit] -= 1;
            }
        }
        self.neighbours.insert(s, neighbours);
    }

    /// May unit `u` join the design (not chosen)?
    pub(super) fn free(&self, u: usize) -> bool {
        self.blocked[u] == 0
    }

    /// Could unit `u` join the design if one chosen unit left it?
    pub(super) fn freeable(&self, u: usize) -> bool {
        self.blocked[u] <= 1
    }

    /// May unit `a` join the design once chosen unit `r` leaves it?
    pub(super) fn free_without(&self, a: usize, r: usize) -> bool {
        if !self.active() {
            return true;
        }
        let by_r = u32::from(self.near(&self.configurations[a], &self.configurations[r]));
        self.blocked[a] == by_r
    }
}
