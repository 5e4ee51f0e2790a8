//! Spacing search: the largest pass spacing whose coating meets the quality limits.
//!
//! Source: spray patent (Tsinghua, Guan & Chen), step 7: if `E > E_m` or `δ > δ_m`, change
//! `b` and repeat steps 2–6. The patent does not say how to change `b`.
//! Input:  spacing bounds, limits, and a function evaluating one spacing at coarse or full
//!         evaluation resolution.
//! Output: the chosen spacing, whether it meets the limits, every spacing tried (with the
//!         resolution it was evaluated at).
//! Cost:   at most 2·[`COARSE_STEPS`] + [`REFINE_ROUNDS`]·[`REFINE_STEPS`] evaluations, the
//!         coarse scan's on the coarse samples (about a quarter as many at twice the
//!         resolution).
//! Deviations (no paper): quality is not monotone in `b` (the overlap of neighbouring
//!         passes swings between ridges and troughs), so bisection could miss the answer:
//!         a coarse scan of evenly spaced spacings, from the widest down to the first
//!         feasible one (narrow spacings cost the most), finds the largest feasible one, then
//!         rounds of finer scans between it and the next coarse spacing push it up (8
//!         coarse spacings, then up to 4 rounds of 2 that each cut the bracket to a third:
//!         the answer is within 1/189 of the range below the true largest feasible spacing
//!         when quality is monotone between the two coarse spacings). The coarse scan may
//!         run on coarser samples; then the largest coarse-feasible spacing is re-evaluated
//!         at full resolution (and, if it fails there, the next smaller coarse-feasible
//!         ones) before refining, and the refinement runs at full resolution, so the chosen
//!         spacing is the largest meeting the limits at full resolution among those tried
//!         at full resolution. Refinement stops early once the bracket is at most
//!         [`REFINE_TOLERANCE`] of the feasible spacing. When no spacing meets the limits,
//!         the full-resolution one with the smallest `max(E/E_m, δ/δ_m)` is chosen (with a
//!         coarse scan: the coarse spacing closest to the limits, re-evaluated at full
//!         resolution).

use super::params::SprayError;
use super::quality::ThicknessStats;
use crate::math::Real;

/// Spacings of the coarse scan.
pub const COARSE_STEPS: usize = 8;
/// Rounds of refinement above the largest feasible coarse spacing.
pub const REFINE_ROUNDS: usize = 4;
/// Spacings tried per refinement round.
pub const REFINE_STEPS: usize = 2;
/// Refinement stops once the bracket above the feasible spacing is at most this fraction
/// of it.
pub const REFINE_TOLERANCE: Real = 0.02;

/// One spacing tried, with the interior figures it gave.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Iteration {
    /// Pass spacing `b`.
    pub spacing: Real,
    /// Evaluation resolution the figures were computed at.
    pub resolution: Real,
    /// Interior mean thickness.
    pub mean: Real,
    /// Interior standard deviation `E`.
    pub std_dev: Real,
    /// Interior error `δ`.
    pub error: Real,
    /// Whether both limits hold.
    pub met: bool,
}

/// The limits `E_m`, `δ_m` (either may be absent).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// `E_m`.
    pub max_std_dev: Option<Real>,
    /// `δ_m`.
    pub max_error: Option<Real>,
}

impl Limits {
    /// Whether figures meet the limits.
    pub fn met(&self, s: &ThicknessStats) -> bool {
        self.max_std_dev.is_none_or(|e| s.std_dev <= e)
            && self.max_error.is_none_or(|d| s.error <= d)
    }

    /// How far figures are from the limits: `max(E/E_m, δ/δ_m)` (≤ 1 when met).
    pub fn excess(&self, s: &ThicknessStats) -> Real {
        let e = self.max_std_dev.map_or(0.0, |e| s.std_dev / e);
        let d = self.max_error.map_or(0.0, |d| s.error / d);
        e.max(d)
    }
}

/// Result of [`search_spacing`].
#[derive(Debug, Clone, PartialEq)]
pub struct SpacingChoice {
    /// The spacing chosen.
    pub spacing: Real,
    /// Whether it meets the limits.
    pub met: bool,
    /// Every spacing tried, in the order tried.
    pub iterations: Vec<Iteration>,
}

/// How a spacing is evaluated: on the coarse samples (scan) or the full ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fidelity {
    /// The coarse evaluation samples (only used to bracket the answer).
    Coarse,
    /// The full evaluation samples (the figures the choice rests on).
    Full,
}

/// Searches `[lo, hi]` for the largest spacing meeting `limits`; `evaluate(b, fidelity)`
/// returns the interior figures of spacing `b` and the resolution they were computed at;
/// `coarse_scan` says whether the coarse scan may use [`Fidelity::Coarse`];
/// `progress(fraction)` is called after each evaluation.
///
/// The chosen spacing is the largest one meeting the limits at full fidelity among those
/// evaluated at full fidelity; when none does, the full-fidelity one with the smallest
/// excess.
pub fn search_spacing(
    lo: Real,
    hi: Real,
    limits: &Limits,
    coarse_scan: bool,
    evaluate: &mut dyn FnMut(Real, Fidelity) -> Result<(ThicknessStats, Real), SprayError>,
    progress: &mut dyn FnMut(f64),
) -> Result<SpacingChoice, SprayError> {
    let total = (COARSE_STEPS + usize::from(coarse_scan) + REFINE_ROUNDS * REFINE_STEPS) as f64;
    let mut iterations: Vec<Iteration> = Vec::new();
    let mut run = |b: Real,
                   fidelity: Fidelity,
                   iterations: &mut Vec<Iteration>|
     -> Result<bool, SprayError> {
        let (s, resolution) = evaluate(b, fidelity)?;
        let met = limits.met(&s);
        iterations.push(Iteration {
            spacing: b,
            resolution,
            mean: s.mean,
            std_dev: s.std_dev,
            error: s.error,
            met,
        });
        progress((iterations.len() as f64 / total).min(1.0));
        Ok(met)
    };
    let coarse: Vec<Real> = if hi > lo {
        (0..COARSE_STEPS)
            .map(|i| lo + (hi - lo) * i as Real / (COARSE_STEPS - 1) as Real)
            .collect()
    } else {
        vec![hi]
    };
    let scan_fidelity = if coarse_scan {
        Fidelity::Coarse
    } else {
        Fidelity::Full
    };
    // Descending: the first spacing meeting the limits is the largest, and the narrow
    // (costly) spacings below it need not be evaluated.
    let mut best: Option<usize> = None;
    for i in (0..coarse.len()).rev() {
        if run(coarse[i], scan_fidelity, &mut iterations)? {
            best = Some(i);
            break;
        }
    }
    let excess = |it: &Iteration| {
        limits.excess(&ThicknessStats {
            std_dev: it.std_dev,
            error: it.error,
            ..Default::default()
        })
    };
    let scanned = iterations.len();
    if coarse_scan {
        // Confirm at full resolution: the largest coarse-feasible spacing and, while that
        // fails, the smaller coarse spacings in turn (at most COARSE_STEPS evaluations);
        // when none was coarse-feasible, only the one closest to the limits.
        let confirm: Vec<usize> = match best {
            Some(top) => (0..=top).rev().collect(),
            None => (0..scanned)
                .min_by(|&a, &b| excess(&iterations[a]).total_cmp(&excess(&iterations[b])))
                .map(|k| coarse.len() - 1 - k)
                .into_iter()
                .collect(),
        };
        best = None;
        for i in confirm {
            if run(coarse[i], Fidelity::Full, &mut iterations)? {
                best = Some(i);
                break;
            }
        }
    }
    let Some(i) = best else {
        let pick = iterations
            .iter()
            .skip(if coarse_scan { scanned } else { 0 })
            .min_by(|a, b| excess(a).total_cmp(&excess(b)))
            .map_or(hi, |it| it.spacing);
        return Ok(SpacingChoice {
            spacing: pick,
            met: false,
            iterations,
        });
    };
    let mut feasible = coarse[i];
    if i + 1 < coarse.len() {
        let mut upper = coarse[i + 1];
        for _ in 0..REFINE_ROUNDS {
            if upper - feasible <= REFINE_TOLERANCE * feasible {
                break;
            }
            let step = (upper - feasible) / (REFINE_STEPS + 1) as Real;
            let mut new_upper = feasible + step;
            let mut found = None;
            for m in 1..=REFINE_STEPS {
                let b = feasible + step * m as Real;
                if run(b, Fidelity::Full, &mut iterations)? {
                    found = Some(b);
                    new_upper = b + step;
                }
            }
            if let Some(b) = found {
                feasible = b;
            }
            upper = new_upper;
        }
    }
    Ok(SpacingChoice {
        spacing: feasible,
        met: true,
        iterations,
    })
}
