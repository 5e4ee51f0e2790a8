//! The speed optimiser's least-squares machinery: the coating matrix `C` (pieces by
//! column), its rows, the normal equations `H = CᵀWC + μL` and cyclic coordinate descent
//! on them within bounds.
//!
//! Source: no paper; the formulation is [`optimise_speeds`](super::speed::optimise_speeds)'s
//! (see its module header). Coordinate descent on a convex quadratic with box constraints
//! lowers the objective at every step and converges to the minimum.
//! Input:  the coating matrix (built by the speed optimiser from the deposition), sample
//!         weights, bounds and the smoothing weight `μ`.
//! Output: `H` by column with its diagonal; dwell factors and residuals after descent.
//! Cost:   `H` is symmetric and only its upper triangle is summed: about half the sum over
//!         samples of (pieces reaching it)², once per weighting; its pattern is found once
//!         and reused for weights that are zero on the same samples; a sweep is linear in the
//!         non-zeros of `H`.
//! Deviations: none (no paper).

use crate::math::Real;

/// Coordinate descent stops once no dwell factor moved by more than this in a sweep.
pub const SWEEP_TOLERANCE: Real = 1e-3;

/// The coating of every piece at the reference speed, column by column.
pub(super) struct Coating {
    /// Column `j` holds entries `start[j]..start[j + 1]`.
    pub(super) start: Vec<usize>,
    pub(super) rows: Vec<u32>,
    pub(super) values: Vec<Real>,
    /// For each piece, whether the next piece continues the same run of gun-on moves.
    pub(super) linked_to_next: Vec<bool>,
}

impl Coating {
    pub(super) fn pieces(&self) -> usize {
        self.start.len() - 1
    }

    pub(super) fn column(&self, j: usize) -> (&[u32], &[Real]) {
        let r = self.start[j]..self.start[j + 1];
        (&self.rows[r.clone()], &self.values[r])
    }

    /// `T = Σ x_j c_j`.
    pub(super) fn thickness(&self, x: &[Real], samples: usize) -> Vec<Real> {
        let mut t = vec![0.0; samples];
        for (j, &xj) in x.iter().enumerate() {
            let (rows, values) = self.column(j);
            for (&i, &v) in rows.iter().zip(values) {
                t[i as usize] += xj * v;
            }
        }
        t
    }
}

/// The coating matrix row by row (sample by sample), for the normal equations. Each row
/// lists its pieces in increasing order.
pub(super) struct Rows {
    start: Vec<usize>,
    pieces: Vec<u32>,
    values: Vec<Real>,
    /// For each entry of the coating matrix (by column), where it lies in its row: the
    /// row's entries from there on are those of the same or later pieces.
    position: Vec<u32>,
}

impl Rows {
    pub(super) fn of(c: &Coating, samples: usize) -> Rows {
        let mut start = vec![0usize; samples + 1];
        for &i in &c.rows {
            start[i as usize + 1] += 1;
        }
        for i in 0..samples {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut pieces = vec![0u32; c.rows.len()];
        let mut values = vec![0.0; c.rows.len()];
        let mut position = vec![0u32; c.rows.len()];
        // Columns in increasing order: each row receives its pieces in increasing order.
        for j in 0..c.pieces() {
            for p in c.start[j]..c.start[j + 1] {
                let at = &mut fill[c.rows[p] as usize];
                pieces[*at] = j as u32;
                values[*at] = c.values[p];
                position[p] = *at as u32;
                *at += 1;
            }
        }
        Rows {
            start,
            pieces,
            values,
            position,
        }
    }
}

/// The box-constrained least-squares problem over the dwell factors, in normal-equation
/// form: `H = CᵀWC + μL` (`L` the smoothing's graph Laplacian), sparse by column (pieces
/// whose coatings overlap), so a coordinate step costs the pieces it overlaps rather than
/// the samples it coats.
pub(super) struct Problem<'a> {
    pub(super) coating: &'a Coating,
    pub(super) rows: &'a Rows,
    /// Bounds of the dwell factors.
    pub(super) lo: Real,
    pub(super) hi: Real,
    /// Weight of the smoothing.
    pub(super) mu: Real,
}

/// Where the entries of `H` lie: by column in full, and its upper triangle (pieces `k ≥ j`
/// of column `j`), which is what is summed (`H` is symmetric), each entry with the places
/// of its value in the full columns (twice off the diagonal).
pub(super) struct Pattern {
    start: Vec<usize>,
    pieces: Vec<u32>,
    upper_start: Vec<usize>,
    upper_pieces: Vec<u32>,
    upper_at: Vec<[usize; 2]>,
}

/// The values of `H` on a [`Pattern`], with its diagonal.
pub(super) struct Gram {
    values: Vec<Real>,
    diagonal: Vec<Real>,
}

impl Problem<'_> {
    /// Adds the upper part of column `j` of `H` (pieces `k ≥ j`) for the sample weights `w`
    /// into the dense `acc`, calling `touch(k)` before each entry `k` it adds to.
    fn accumulate(&self, j: usize, w: &[Real], acc: &mut [Real], mut touch: impl FnMut(usize)) {
        let c = self.coating;
        for p in c.start[j]..c.start[j + 1] {
            let i = c.rows[p] as usize;
            let wa = w[i] * c.values[p];
            if wa == 0.0 {
                continue;
            }
            // The row from piece j on (its pieces increase).
            let r = self.rows.position[p] as usize..self.rows.start[i + 1];
            for (&k, &b) in self.rows.pieces[r.clone()].iter().zip(&self.rows.values[r]) {
                touch(k as usize);
                acc[k as usize] += wa * b;
            }
        }
        // The smoothing: μ on the diagonal per link, −μ towards the next piece (the link to
        // the previous one is that piece's upper entry).
        let links =
            usize::from(j > 0 && c.linked_to_next[j - 1]) + usize::from(c.linked_to_next[j]);
        if links > 0 {
            touch(j);
            acc[j] += self.mu * links as Real;
        }
        if c.linked_to_next[j] {
            touch(j + 1);
            acc[j + 1] -= self.mu;
        }
    }

    /// `H` for the sample weights `w`, and where its entries lie.
    pub(super) fn gram(&self, w: &[Real]) -> (Pattern, Gram) {
        let m = self.coating.pieces();
        let mut upper_start = Vec::with_capacity(m + 1);
        upper_start.push(0);
        let mut upper_pieces: Vec<u32> = Vec::new();
        let mut upper_values: Vec<Real> = Vec::new();
        let mut acc = vec![0.0; m];
        let mut seen = vec![false; m];
        for j in 0..m {
            let from = upper_pieces.len();
            self.accumulate(j, w, &mut acc, |k| {
                if !seen[k] {
                    seen[k] = true;
                    upper_pieces.push(k as u32);
                }
            });
            // The same sums as [`Problem::regram`] forms on this pattern.
            for &k in &upper_pieces[from..] {
                let k = k as usize;
                upper_values.push(acc[k]);
                seen[k] = false;
                acc[k] = 0.0;
            }
            upper_start.push(upper_pieces.len());
        }
        // The full columns: column j holds its upper entries and, mirrored, the entries j of
        // the columns before it.
        let mut start = vec![0usize; m + 1];
        for j in 0..m {
            for &k in &upper_pieces[upper_start[j]..upper_start[j + 1]] {
                start[j + 1] += 1;
                if k as usize != j {
                    start[k as usize + 1] += 1;
                }
            }
        }
        for j in 0..m {
            start[j + 1] += start[j];
        }
        let mut fill = start.clone();
        let mut pieces = vec![0u32; start[m]];
        let mut upper_at = vec![[0usize; 2]; upper_pieces.len()];
        for j in 0..m {
            for e in upper_start[j]..upper_start[j + 1] {
                let k = upper_pieces[e] as usize;
                let a = fill[j];
                pieces[a] = k as u32;
                fill[j] += 1;
                let b = if k != j {
                    let b = fill[k];
                    pieces[b] = j as u32;
                    fill[k] += 1;
                    b
                } else {
                    a
                };
                upper_at[e] = [a, b];
            }
        }
        let pattern = Pattern {
            start,
            pieces,
            upper_start,
            upper_pieces,
            upper_at,
        };
        let mut values = vec![0.0; pattern.pieces.len()];
        let mut diagonal = vec![0.0; m];
        for (j, d) in diagonal.iter_mut().enumerate() {
            let r = pattern.upper_start[j]..pattern.upper_start[j + 1];
            let upper = pattern.upper_pieces[r.clone()]
                .iter()
                .zip(&pattern.upper_at[r.clone()])
                .zip(&upper_values[r]);
            for ((&k, &[a, b]), &v) in upper {
                values[a] = v;
                values[b] = v;
                if k as usize == j {
                    *d = v;
                }
            }
        }
        (pattern, Gram { values, diagonal })
    }

    /// `H` for the sample weights `w` on `pattern`, built for weights that are zero on the
    /// same samples (or on fewer): no bookkeeping of which entries a column touches.
    pub(super) fn regram(&self, w: &[Real], pattern: &Pattern) -> Gram {
        let m = self.coating.pieces();
        let mut values = vec![0.0; pattern.pieces.len()];
        let mut diagonal = vec![0.0; m];
        let mut acc = vec![0.0; m];
        for (j, d) in diagonal.iter_mut().enumerate() {
            self.accumulate(j, w, &mut acc, |_| {});
            for e in pattern.upper_start[j]..pattern.upper_start[j + 1] {
                let k = pattern.upper_pieces[e] as usize;
                let v = acc[k];
                let [a, b] = pattern.upper_at[e];
                values[a] = v;
                values[b] = v;
                if k == j {
                    *d = v;
                }
                acc[k] = 0.0;
            }
        }
        Gram { values, diagonal }
    }

    /// Cyclic coordinate descent from `x` with residuals `r = T − T*`, sample weights `w` and
    /// `H` for them on `pattern`; at most `sweeps` sweeps. `r` is brought up to date at the
    /// end.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn descend(
        &self,
        x: &mut [Real],
        r: &mut [Real],
        w: &[Real],
        sweeps: usize,
        pattern: &Pattern,
        h: &Gram,
    ) {
        let c = self.coating;
        let m = c.pieces();
        // Gradient (halved): CᵀW r + μ L x.
        let mut g: Vec<Real> = (0..m)
            .map(|j| {
                let (rows, values) = c.column(j);
                let mut g: Real = rows
                    .iter()
                    .zip(values)
                    .map(|(&i, &v)| w[i as usize] * v * r[i as usize])
                    .sum();
                if j > 0 && c.linked_to_next[j - 1] {
                    g += self.mu * (x[j] - x[j - 1]);
                }
                if c.linked_to_next[j] {
                    g += self.mu * (x[j] - x[j + 1]);
                }
                g
            })
            .collect();
        let start_x = x.to_vec();
        for _ in 0..sweeps {
            let mut largest: Real = 0.0;
            for j in 0..m {
                if h.diagonal[j] <= 0.0 {
                    continue;
                }
                let new = (x[j] - g[j] / h.diagonal[j]).clamp(self.lo, self.hi);
                let d = new - x[j];
                if d != 0.0 {
                    x[j] = new;
                    let r = pattern.start[j]..pattern.start[j + 1];
                    for (&k, &v) in pattern.pieces[r.clone()].iter().zip(&h.values[r]) {
                        g[k as usize] += v * d;
                    }
                    largest = largest.max(d.abs());
                }
            }
            if largest <= SWEEP_TOLERANCE {
                break;
            }
        }
        // r += C (x − x_start).
        for j in 0..m {
            let d = x[j] - start_x[j];
            if d != 0.0 {
                let (rows, values) = c.column(j);
                for (&i, &v) in rows.iter().zip(values) {
                    r[i as usize] += v * d;
                }
            }
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A small linear congruential sequence in [0, 1).
    pub(in crate::spray) fn sequence(seed: u64) -> impl FnMut() -> Real {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as Real / (1u64 << 53) as Real
        }
    }

    /// `H` summed over its upper triangle and mirrored is the dense `CᵀWC + μL`, exactly
    /// symmetric, for the first weights and for others on the same pattern.
    #[test]
    // Dense matrices read best indexed.
    #[allow(clippy::needless_range_loop)]
    fn the_normal_equations_are_the_dense_product_and_symmetric() {
        let (m, n, mu) = (7usize, 12usize, 0.3);
        let mut next = sequence(7);
        // Piece j reaches the samples within 2 of 2j − 1, listed from the last.
        let mut dense = vec![vec![0.0; m]; n];
        let (mut start, mut rows, mut values) = (vec![0usize], Vec::new(), Vec::new());
        for j in 0..m {
            for i in (0..n).rev() {
                if (i as i64 - 2 * j as i64 + 1).abs() <= 2 {
                    let v = 0.5 + next();
                    dense[i][j] = v;
                    rows.push(i as u32);
                    values.push(v);
                }
            }
            start.push(rows.len());
        }
        let coating = Coating {
            start,
            rows,
            values,
            linked_to_next: vec![true, true, false, true, true, true, false],
        };
        let rows = Rows::of(&coating, n);
        let problem = Problem {
            coating: &coating,
            rows: &rows,
            lo: 0.5,
            hi: 2.0,
            mu,
        };
        let reference = |w: &[Real]| {
            let mut h = vec![vec![0.0; m]; m];
            for (j, hj) in h.iter_mut().enumerate() {
                for (k, hjk) in hj.iter_mut().enumerate() {
                    *hjk = (0..n)
                        .map(|i| w[i] * dense[i][j] * dense[i][k])
                        .sum::<Real>();
                }
            }
            for j in 0..m - 1 {
                if coating.linked_to_next[j] {
                    h[j][j] += mu;
                    h[j + 1][j + 1] += mu;
                    h[j][j + 1] -= mu;
                    h[j + 1][j] -= mu;
                }
            }
            h
        };
        let check = |pattern: &Pattern, gram: &Gram, w: &[Real]| {
            let h = reference(w);
            let mut found = vec![vec![None; m]; m];
            for j in 0..m {
                for e in pattern.start[j]..pattern.start[j + 1] {
                    found[pattern.pieces[e] as usize][j] = Some(gram.values[e]);
                }
            }
            for j in 0..m {
                assert!((gram.diagonal[j] - h[j][j]).abs() <= 1e-12, "diagonal {j}");
                for k in 0..m {
                    match found[k][j] {
                        Some(v) => {
                            assert!((v - h[k][j]).abs() <= 1e-12, "H[{k}][{j}] {v} {}", h[k][j]);
                            assert_eq!(found[j][k].map(Real::to_bits), Some(v.to_bits()));
                        }
                        None => assert_eq!(h[k][j], 0.0, "H[{k}][{j}] left out"),
                    }
                }
            }
        };
        // Sample 3 carries no weight: pieces meeting only there are not coupled.
        let weights = |next: &mut dyn FnMut() -> Real| {
            (0..n)
                .map(|i| if i == 3 { 0.0 } else { 0.5 + next() })
                .collect::<Vec<Real>>()
        };
        let w = weights(&mut next);
        let (pattern, gram) = problem.gram(&w);
        check(&pattern, &gram, &w);
        let w2 = weights(&mut next);
        check(&pattern, &problem.regram(&w2, &pattern), &w2);
    }
}
