//! The tangential memory of the ball's contact: a bed of independent spring–slider (Jenkins)
//! elements in parallel, an Iwan model whose thresholds follow the Hertz pressure — exactly the
//! method of dimensionality reduction (MDR) of V. L. Popov & M. Heß, *Method of Dimensionality
//! Reduction in Contact Mechanics and Friction*, Springer 2015, ch. 2–3 (sphere: ch. 3, tangential
//! contact with arbitrary loading history: ch. 4).
//!
//! Model. The sphere of radius R becomes a 1-D profile g(x) = x²/R pressed by the approach d
//! into a row of springs, each of width Δx at position x:
//! * normal: n(x) = E*Δx (d − g(x))₊ — summed, (4/3)E*√R d^{3/2}, Hertz's law, with the contact
//!   half-width a = √(Rd), Hertz's radius;
//! * tangential: spring G_MΔx with G_M = 4G* (1/G_M = (2 − ν₁)/4G₁ + (2 − ν₂)/4G₂), deflection
//!   e(x), force G_MΔx e bounded by μ n(x), i.e. |e| ≤ μ(E*/G_M)(d − g)₊; a spring that lifts off
//!   (d ≤ g) loses its deflection.
//!
//! For monotonic Q at constant N the bed gives Mindlin's curve δ_t(Q) exactly; for reversals it
//! gives the Mindlin–Deresiewicz (Masing) branches and their loop energy; for simultaneously
//! varying N and Q it gives the Cattaneo–Mindlin-type solution of Jäger / Popov–Heß for arbitrary
//! load histories (valid while the stick zone's memory is described by its edge alone, the
//! assumption of those solutions: β = 0, quasi-static, no torsion). Each step is a return mapping:
//! trial e + Δs, clamped to ±limit at the step's end (backward Euler on the friction cone, exact
//! for the rate-independent element).
//!
//! Discretisation: springs at midpoints x_i = (i + ½)h of [0, extent], counted twice (±x). The
//! error of the sums is O(h²) where the contact edge falls inside a cell (tested: order ≈ 2 for
//! the Mindlin curve and the loop energy).
//!
//! Energy (exact per step, any step length): with f̄_i = k(e_i⁰ + e_i¹)/2 and Δp_i = trial − e_i¹
//! the slip of spring i, Σf̄_iΔs = ΔU + D, ΔU = Σ½k(e¹² − e⁰²), D = Σf̄_iΔp_i.

use serde::Serialize;

/// Result of advancing the bed by one step (units of the bed: force and length as built).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct BedStep {
    /// Step-mean tangential force Σf̄_i.
    pub mean_force: f64,
    /// End-of-step tangential force.
    pub end_force: f64,
    /// Friction dissipation Σf̄_iΔp_i.
    pub dissipation: f64,
    /// Change of the stored tangential elastic energy.
    pub energy_change: f64,
    /// Springs that slipped in the step.
    pub slipping: usize,
    /// Springs in contact at the step's end.
    pub in_contact: usize,
}

/// A row of spring–slider elements under a parabolic profile (one side, counted twice).
#[derive(Debug, Clone, PartialEq)]
pub struct SpringBed {
    /// g_i = x_i²/R, ascending (length unit of the bed).
    profile: Vec<f64>,
    /// Tangential stiffness of one spring, both sides: 2hG_M (force per length unit).
    stiffness: f64,
    /// Normal stiffness of one spring, both sides: 2hE* (force per length unit).
    normal_stiffness: f64,
    /// μE*/G_M: deflection limit per unit of local indentation.
    limit_factor: f64,
    /// Deflection e_i of each spring.
    deflection: Vec<f64>,
    /// Springs that may hold a deflection (all beyond are zero).
    active: usize,
    /// Extent of the bed (largest contact half-width it can hold, length unit of x).
    extent: f64,
}

impl SpringBed {
    /// The MDR bed of a sphere (SI): `springs` elements over [0, extent_m].
    pub fn sphere(
        radius_m: f64,
        extent_m: f64,
        springs: usize,
        effective_modulus_pa: f64,
        effective_shear_modulus_pa: f64,
        friction_coefficient: f64,
    ) -> Self {
        let n = springs.max(1);
        let h = extent_m / n as f64;
        let g_m = 4.0 * effective_shear_modulus_pa;
        let profile = (0..n)
            .map(|i| ((i as f64 + 0.5) * h).powi(2) / radius_m)
            .collect();
        Self {
            profile,
            stiffness: 2.0 * h * g_m,
            normal_stiffness: 2.0 * h * effective_modulus_pa,
            limit_factor: friction_coefficient * effective_modulus_pa / g_m,
            deflection: vec![0.0; n],
            active: 0,
            extent: extent_m,
        }
    }

    /// The same bed in other units: lengths divided by `length`, forces by `force`.
    pub fn rescaled(mut self, length: f64, force: f64) -> Self {
        for g in &mut self.profile {
            *g /= length;
        }
        for e in &mut self.deflection {
            *e /= length;
        }
        self.stiffness *= length / force;
        self.normal_stiffness *= length / force;
        self
    }

    /// Number of springs.
    pub fn len(&self) -> usize {
        self.profile.len()
    }

    /// Whether the bed has no springs (never: at least one is laid).
    pub fn is_empty(&self) -> bool {
        self.profile.is_empty()
    }

    /// Largest approach the bed resolves (the profile at its outer edge).
    pub fn max_approach(&self) -> f64 {
        let h = self.extent / self.len() as f64;
        let last = self.profile[self.len() - 1];
        // g at the extent = g_last · (extent / x_last)².
        let x_last = (self.len() as f64 - 0.5) * h;
        last * (self.extent / x_last).powi(2)
    }

    /// Springs touching at approach d (profile below d).
    fn touching(&self, d: f64) -> usize {
        self.profile.partition_point(|&g| g < d)
    }

    /// Discretised normal force Σ 2hE*(d − g_i)₊ (the bed's own Hertz force).
    pub fn normal_force(&self, d: f64) -> f64 {
        let n = self.touching(d);
        self.normal_stiffness * self.profile[..n].iter().map(|g| d - g).sum::<f64>()
    }

    /// Current tangential force Σk e_i.
    pub fn force(&self) -> f64 {
        self.stiffness * self.deflection[..self.active].iter().sum::<f64>()
    }

    /// Stored tangential energy Σ½k e_i².
    pub fn energy(&self) -> f64 {
        0.5 * self.stiffness
            * self.deflection[..self.active]
                .iter()
                .map(|e| e * e)
                .sum::<f64>()
    }

    /// Deflections (read only).
    pub fn deflections(&self) -> &[f64] {
        &self.deflection
    }

    /// Every spring in contact at approach d at its friction limit with the sign of `sign`
    /// (the state after long sliding in that direction); springs out of contact at zero.
    pub fn saturate(&mut self, d: f64, sign: f64) {
        let n = self.touching(d);
        for (i, e) in self.deflection.iter_mut().enumerate() {
            *e = if i < n {
                sign.signum() * self.limit_factor * (d - self.profile[i])
            } else {
                0.0
            };
        }
        self.active = n;
    }

    /// Release every spring (no tangential load).
    pub fn release(&mut self) {
        self.deflection.iter_mut().for_each(|e| *e = 0.0);
        self.active = 0;
    }

    /// The step to approach `d1` with relative tangential displacement `ds` (stator minus
    /// ball), without changing the bed.
    pub fn trial(&self, d1: f64, ds: f64) -> BedStep {
        let touching = self.touching(d1);
        let mut books = Books::default();
        for i in 0..touching.max(self.active) {
            books.add(self.deflection[i], self.limit(i, touching, d1), ds);
        }
        books.finish(self.stiffness, touching)
    }

    /// Advance the bed by the step and return its books.
    pub fn commit(&mut self, d1: f64, ds: f64) -> BedStep {
        let touching = self.touching(d1);
        let mut books = Books::default();
        for i in 0..touching.max(self.active) {
            let limit = self.limit(i, touching, d1);
            self.deflection[i] = books.add(self.deflection[i], limit, ds);
        }
        self.active = touching;
        books.finish(self.stiffness, touching)
    }

    fn limit(&self, i: usize, touching: usize, d: f64) -> f64 {
        if i < touching {
            self.limit_factor * (d - self.profile[i])
        } else {
            0.0
        }
    }
}

/// Running sums of one step over the springs (in deflection units).
#[derive(Default)]
struct Books {
    mean: f64,
    end: f64,
    dissipation: f64,
    energy_change: f64,
    slipping: usize,
}

impl Books {
    /// Return-map one spring from e0 by ds onto |e| ≤ limit; add its books; return e1.
    #[inline]
    fn add(&mut self, e0: f64, limit: f64, ds: f64) -> f64 {
        let trial = e0 + ds;
        let e1 = trial.clamp(-limit, limit);
        if e1 != trial {
            self.slipping += 1;
        }
        let mean = 0.5 * (e0 + e1);
        self.mean += mean;
        self.end += e1;
        self.dissipation += mean * (trial - e1);
        self.energy_change += 0.5 * (e1 * e1 - e0 * e0);
        e1
    }

    fn finish(self, k: f64, in_contact: usize) -> BedStep {
        BedStep {
            mean_force: k * self.mean,
            end_force: k * self.end,
            dissipation: k * self.dissipation,
            energy_change: k * self.energy_change,
            slipping: self.slipping,
            in_contact,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bed_books_close_for_a_large_reversing_step() {
        let mut bed = SpringBed::sphere(1.0, 1.2, 50, 1.0, 0.3, 0.4);
        bed.saturate(1.0, -1.0);
        let u0 = bed.energy();
        let step = bed.commit(0.8, 0.9);
        let work = step.mean_force * 0.9;
        let closure = work - step.energy_change - step.dissipation;
        assert!(
            closure.abs() < 1e-14,
            "tangential work − ΔU − D = {closure}"
        );
        assert!(
            (bed.energy() - u0 - step.energy_change).abs() < 1e-14,
            "stored energy change"
        );
    }
}
