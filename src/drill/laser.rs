//! Surface normal at a hole from four laser displacement sensors, and simulated readings.
//!
//! Source: Bi, Tu, Fang, Shen, Li, "Correcting method of hole position for flexible track
//!         automatic drilling system", J. Zhejiang Univ. (Eng. Sci.) 49(10), 2015, §3.1 and
//!         the example of §4.1 (sensors on a rectangle, beams parallel to the head axis A0→M).
//! Input:  calibrated beam origins `A1..A4` (in cyclic order around the head), unit beam
//!         directions and the four readings (distances along the beams, model units).
//! Output: `Q_i = A_i + reading_i · d_i`; the midpoints `M1..M4` of `Q1Q2, Q2Q3, Q3Q4, Q4Q1`
//!         form a parallelogram (Varignon), whose unit normal `M1M2 × M1M4` is returned,
//!         oriented back towards the sensors (against the mean beam direction).
//! Cost:   O(1); simulated readings cost one ray cast each on a [`MeshIndex`].
//! Deviations: the paper leaves the sign to the cross product (its example prints the inward
//!         normal); here it always points towards the sensors, i.e. out of the part. Since
//!         `M1M2 = (Q3 − Q1)/2` and `M1M4 = (Q4 − Q2)/2`, the normal is that of the diagonals,
//!         and degenerate readings (coincident or collinear points, or points in crossed order)
//!         are refused rather than giving an arbitrary normal.

use super::DrillError;
use crate::math::{Point3, Real, Vector3};
use crate::mesh::MeshIndex;

/// A beam direction counts as unit when its length is within this of 1.
pub const UNIT_DIRECTION_TOLERANCE: Real = 1e-6;
/// Two laser points closer than this fraction of the largest distance between any two of
/// them count as coincident.
pub const LASER_COINCIDENCE_RATIO: Real = 1e-6;
/// The diagonals `Q1Q3` and `Q2Q4` count as parallel (points collinear or in crossed order)
/// when the sine of their angle is below this.
pub const LASER_MIN_DIAGONAL_SINE: Real = 1e-6;
/// The beams graze the surface (the normal's side is undecidable) when the cosine between the
/// normal and the mean beam direction is below this.
pub const LASER_MIN_INCIDENCE_COSINE: Real = 1e-3;

/// The surface points `Q_i = A_i + reading_i · d_i` hit by the four beams, after checking the
/// input (finite values, unit directions, non-negative readings).
pub fn laser_points(
    origins: &[Point3; 4],
    directions: &[Vector3; 4],
    readings: &[Real; 4],
) -> Result<[Point3; 4], DrillError> {
    for i in 0..4 {
        let beam = i + 1;
        for (name, value) in origins[i]
            .coords
            .iter()
            .map(|&v| ("origin", v))
            .chain(directions[i].iter().map(|&v| ("direction", v)))
            .chain(std::iter::once(("reading", readings[i])))
        {
            if !value.is_finite() {
                return Err(DrillError::NonFinite {
                    name: format!("{name} of beam {beam}"),
                    value,
                });
            }
        }
        check_unit_direction(beam, &directions[i])?;
        if readings[i] < 0.0 {
            return Err(DrillError::NegativeReading {
                beam,
                value: readings[i],
            });
        }
    }
    Ok(std::array::from_fn(|i| {
        origins[i] + directions[i] * readings[i]
    }))
}

/// Unit surface normal from four laser readings (§3.1), pointing back towards the sensors.
pub fn normal_from_lasers(
    origins: &[Point3; 4],
    directions: &[Vector3; 4],
    readings: &[Real; 4],
) -> Result<Vector3, DrillError> {
    let q = laser_points(origins, directions, readings)?;
    let mean_direction: Vector3 = directions.iter().sum();
    normal_from_points(&q, &mean_direction)
}

/// Unit normal of the Varignon parallelogram of four points in cyclic order, oriented so that
/// it points against `beam_direction` (towards whoever looked at the points).
pub fn normal_from_points(
    q: &[Point3; 4],
    beam_direction: &Vector3,
) -> Result<Vector3, DrillError> {
    let mut spread: Real = 0.0;
    for i in 0..4 {
        for j in i + 1..4 {
            spread = spread.max((q[j] - q[i]).norm());
        }
    }
    for i in 0..4 {
        for j in i + 1..4 {
            if (q[j] - q[i]).norm() <= LASER_COINCIDENCE_RATIO * spread {
                return Err(DrillError::DegenerateLaserPoints(format!(
                    "points Q{} and Q{} coincide",
                    i + 1,
                    j + 1
                )));
            }
        }
    }
    // Step: M1M2 = (Q3 − Q1)/2 and M1M4 = (Q4 − Q2)/2 (midline theorem), so their cross
    // product is a quarter of the diagonals' (Eq. 1 up to that factor).
    let d13 = q[2] - q[0];
    let d24 = q[3] - q[1];
    let cross = d13.cross(&d24);
    let sine = cross.norm() / (d13.norm() * d24.norm());
    if sine.is_nan() || sine < LASER_MIN_DIAGONAL_SINE {
        return Err(DrillError::DegenerateLaserPoints(format!(
            "the diagonals Q1Q3 and Q2Q4 are parallel (sine of their angle {sine:e}): the points \
             are collinear or not in cyclic order around the head"
        )));
    }
    let mut normal = cross / cross.norm();
    let beam = beam_direction.norm();
    let cosine = normal.dot(beam_direction) / beam;
    if cosine.is_nan() || cosine.abs() < LASER_MIN_INCIDENCE_COSINE {
        return Err(DrillError::DegenerateLaserPoints(format!(
            "the beams graze the surface (cosine to its normal {cosine:e}), so the normal's side \
             is undecidable"
        )));
    }
    if cosine > 0.0 {
        normal = -normal;
    }
    Ok(normal)
}

/// How the four beams of a [`SensorHead`] are aimed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BeamAim {
    /// All beams parallel to the head axis (the paper's example, §4.1).
    #[default]
    Parallel,
    /// Each beam from its corner towards the point at `standoff` along the head axis.
    Converging,
}

/// A virtual sensor head: four beam origins on a `width × height` rectangle centred on the
/// head axis, `standoff` from the hole (model units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorHead {
    /// Rectangle side along the head's width direction.
    pub width: Real,
    /// Rectangle side along the other direction in the head plane.
    pub height: Real,
    /// Distance from the rectangle's centre `A0` to the hole along the axis.
    pub standoff: Real,
    /// How the beams are aimed.
    pub aim: BeamAim,
}

impl SensorHead {
    /// Beam origins (cyclic: (−w,−h), (+w,−h), (+w,+h), (−w,+h) halves) and unit directions
    /// for a head centred at `centre` looking along `axis` (towards the part); `width_dir` is
    /// projected into the head plane to orient the rectangle.
    pub fn beams(
        &self,
        centre: &Point3,
        axis: &Vector3,
        width_dir: &Vector3,
    ) -> Result<([Point3; 4], [Vector3; 4]), DrillError> {
        for (name, value) in [
            ("width", self.width),
            ("height", self.height),
            ("standoff", self.standoff),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(DrillError::BadParam {
                    name,
                    value,
                    allowed: "the sensor head's sizes must be finite and > 0",
                });
            }
        }
        let axis = unit_or_err("head axis", axis)?;
        let e1 = unit_or_err(
            "head width direction",
            &(width_dir - axis * axis.dot(width_dir)),
        )?;
        let e2 = axis.cross(&e1);
        let (hw, hh) = (0.5 * self.width, 0.5 * self.height);
        let origins =
            [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)].map(|(a, b)| centre + e1 * a + e2 * b);
        let target = centre + axis * self.standoff;
        let directions = origins.map(|o| match self.aim {
            BeamAim::Parallel => axis,
            // target ≠ o: o lies in the head plane, target at standoff > 0 from it.
            BeamAim::Converging => (target - o).normalize(),
        });
        Ok((origins, directions))
    }

    /// Beams for a head placed at `standoff` along the outward `normal` of `hole`, looking
    /// back at it.
    pub fn beams_at_hole(
        &self,
        hole: &Point3,
        normal: &Vector3,
        width_dir: &Vector3,
    ) -> Result<([Point3; 4], [Vector3; 4]), DrillError> {
        let n = unit_or_err("hole normal", normal)?;
        self.beams(&(hole + n * self.standoff), &-n, width_dir)
    }
}

/// Simulated readings: the distance along each beam to the first mesh triangle it hits,
/// NaN where it misses. Directions must be unit vectors.
pub fn laser_readings(
    index: &MeshIndex,
    origins: &[Point3],
    directions: &[Vector3],
) -> Result<Vec<Real>, DrillError> {
    if origins.len() != directions.len() {
        return Err(DrillError::BadParam {
            name: "directions",
            value: directions.len() as Real,
            allowed: "there must be as many beam directions as beam origins",
        });
    }
    let mut readings = Vec::with_capacity(origins.len());
    for (i, (o, d)) in origins.iter().zip(directions).enumerate() {
        if let Some(&value) = o.coords.iter().chain(d.iter()).find(|v| !v.is_finite()) {
            return Err(DrillError::NonFinite {
                name: format!("origin or direction of beam {}", i + 1),
                value,
            });
        }
        check_unit_direction(i + 1, d)?;
        readings.push(
            index
                .cast_ray(o, d, Real::INFINITY)
                .map_or(Real::NAN, |hit| hit.distance),
        );
    }
    Ok(readings)
}

fn check_unit_direction(beam: usize, d: &Vector3) -> Result<(), DrillError> {
    let length = d.norm();
    if (length - 1.0).abs() > UNIT_DIRECTION_TOLERANCE {
        return Err(DrillError::BadBeamDirection { beam, length });
    }
    Ok(())
}

fn unit_or_err(name: &'static str, v: &Vector3) -> Result<Vector3, DrillError> {
    let length = v.norm();
    if !(length.is_finite() && length > 0.0) {
        return Err(DrillError::BadParam {
            name,
            value: length,
            allowed: "must be a finite non-zero vector (the value shown is its length)",
        });
    }
    Ok(v / length)
}
