//! Coating thickness left by a trajectory: parabolic deposition with the curved-surface
//! correction, summed over time samples.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), claims 5–7 as restated in SEEDS.md:
//! planar rate `f(r) = A(1 − r²/R²)` for `r ≤ R`, `R = h·tan(α/2)`, `A = 2ηQ/(πR²)`
//! (mass balance `∫f dA = ηQ`); on the surface `F(M') = F(M)·(h/l)²·cos λ / cos θ` with `l`
//! the axial distance of `M'` from the gun, `θ` the ray's angle to the gun axis, `λ` the
//! angle between the ray and the surface normal at `M'`; `cos λ ≤ 0` gets nothing. The
//! trajectory is cut into time samples; each adds `F·Δt` to every point in its cone.
//! Input:  tool path (gun-on moves), evaluation samples bucketed in a [`PointGrid`].
//! Output: thickness per sample, mesh unit.
//! Cost:   O(time samples × points per cone): each sample visits only the grid cells around
//!         its cone, truncated at an axial distance of [`MAX_AXIAL_RATIO`]·h.
//! Deviations: occlusion by other parts of the mesh is ignored (every point in the cone
//!         with `cos λ > 0` is coated); points farther than `MAX_AXIAL_RATIO·h` along the axis
//!         are ignored; the gun moves at constant speed `v` along every gun-on move (arcs
//!         included), position interpolated linearly and axis normalised-linearly between
//!         poses; each time sample sits at the middle of its interval (midpoint rule).

use super::grid::PointGrid;
use super::params::{SprayError, MAX_TIME_SAMPLES};
use super::samples::EvaluationSamples;
use crate::math::{Real, Vector3};
use crate::toolpath::ToolPath;

/// Points farther than this multiple of the standoff along the gun axis get nothing.
pub const MAX_AXIAL_RATIO: Real = 1.5;

/// The spray model: footprint radius `R`, peak rate `A`, standoff `h`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SprayModel {
    /// Footprint radius `R` on the plane at the standoff.
    pub radius: Real,
    /// Peak rate `A`, mesh unit of thickness per second.
    pub peak_rate: Real,
    /// Standoff `h`.
    pub standoff: Real,
}

impl SprayModel {
    /// Rate `F(M')` at offset `w` from the gun (axis `a`, unit) on a surface of normal `n`.
    #[inline]
    pub fn rate(&self, w: &Vector3, a: &Vector3, n: &Vector3) -> Real {
        let l = w.dot(a);
        if l <= 0.0 || l > MAX_AXIAL_RATIO * self.standoff {
            return 0.0;
        }
        let dist2 = w.norm_squared();
        let rho2 = (dist2 - l * l).max(0.0);
        // r on the plane at distance h along the same ray.
        let r2 = rho2 * (self.standoff * self.standoff) / (l * l);
        let big_r2 = self.radius * self.radius;
        if r2 >= big_r2 {
            return 0.0;
        }
        let dist = dist2.sqrt();
        let cos_lambda = -w.dot(n) / dist;
        if cos_lambda <= 0.0 {
            return 0.0;
        }
        let cos_theta = l / dist;
        let planar = self.peak_rate * (1.0 - r2 / big_r2);
        planar * (self.standoff / l).powi(2) * cos_lambda / cos_theta
    }
}

/// Number of time samples the trajectory takes at step `v·Δt`.
pub fn time_sample_count(path: &ToolPath, step_length: Real) -> usize {
    let mut count = 0usize;
    for pair in path.poses.windows(2) {
        if pair[1].kind.process_on() {
            let length = (pair[1].position - pair[0].position).norm();
            count = count.saturating_add((length / step_length).ceil() as usize);
        }
    }
    count
}

/// Thickness per sample after spraying `path` at speed `speed` with time step `time_step`.
pub fn deposit(
    path: &ToolPath,
    samples: &EvaluationSamples,
    grid: &PointGrid,
    model: &SprayModel,
    speed: Real,
    time_step: Real,
) -> Result<Vec<Real>, SprayError> {
    let step_length = speed * time_step;
    let count = time_sample_count(path, step_length);
    if count > MAX_TIME_SAMPLES {
        return Err(SprayError::TooManyTimeSamples {
            time_step,
            samples: count,
        });
    }
    let mut thickness = vec![0.0; samples.positions.len()];
    let reach = MAX_AXIAL_RATIO * model.standoff;
    let spread = model.radius * MAX_AXIAL_RATIO;
    for pair in path.poses.windows(2) {
        let (p0, p1) = (&pair[0], &pair[1]);
        if !p1.kind.process_on() {
            continue;
        }
        let length = (p1.position - p0.position).norm();
        if length <= 0.0 {
            continue;
        }
        let n = (length / step_length).ceil().max(1.0) as usize;
        let dt = length / (n as Real * speed);
        for s in 0..n {
            let tau = (s as Real + 0.5) / n as Real;
            let gun = p0.position + (p1.position - p0.position) * tau;
            let axis = (p0.axis * (1.0 - tau) + p1.axis * tau).normalize();
            // Bounding box of the cone truncated at the axial reach.
            let tip = gun.coords + axis * reach;
            let half = axis.map(|c| spread * (1.0 - c * c).max(0.0).sqrt());
            let lo = gun.coords.inf(&(tip - half));
            let hi = gun.coords.sup(&(tip + half));
            grid.for_each_in_box(&lo, &hi, |i| {
                let w = samples.positions[i] - gun;
                let f = model.rate(&w, &axis, &samples.normals[i]);
                if f > 0.0 {
                    thickness[i] += f * dt;
                }
            });
        }
    }
    Ok(thickness)
}
