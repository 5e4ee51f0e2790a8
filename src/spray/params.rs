//! Spray parameters, their defaults and validation, and the errors of the spray planner.
//!
//! Source: patent "a trajectory planning method for curved-surface spraying" (Tsinghua
//! University, Guan Liwen, Chen Lu), step 1 (process parameters `b, h, v, Q, α`), step 4
//! (`β_T`), step 7 (`E_m, δ_m`). The remaining parameters (extension, time step,
//! resolution, edge exclusion, spacing bounds, target thickness) are this planner's own.

use crate::math::{Compact, Real, Vector3};

/// Most evaluation samples a plan may create; a finer resolution is refused (memory: about
/// 80 bytes a sample with its display triangles).
pub const MAX_SAMPLES: usize = 2_000_000;
/// Most trajectory time samples one deposition may take (bounds the work of a tiny time step).
pub const MAX_TIME_SAMPLES: usize = 20_000_000;
/// Most entries (a sample reached by a piece of the passes) the speed optimiser's coating
/// matrix may hold: about 28 bytes each with its row-wise copy, 670 MB at the most. The
/// real skins measured need 2 to 17 entries a sample; surfaces stacked within the gun's
/// reach (every one coated at once, as occlusion is not modelled) need one for each.
pub const MAX_COATING_ENTRIES: usize = 24_000_000;
/// Most scan planes one plan may have (bounds the work of a tiny spacing).
pub const MAX_PLANES: usize = 100_000;

/// A count of samples as messages show it: the whole number ([`Compact`]), or "more than
/// 1e308" where even a float overflows (a resolution or time step of 1e-300).
struct Count(Real);

impl std::fmt::Display for Count {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.is_finite() {
            write!(f, "about {}", Compact(self.0.round()))
        } else {
            f.write_str("more than 1e308")
        }
    }
}

/// Why spray planning was refused. Messages name the parameter as the JavaScript API spells it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SprayError {
    /// A number is NaN or infinite.
    #[error("{name} must be a finite number, got {}", Compact(*.value))]
    NotFinite {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: Real,
    },
    /// A number is outside its allowed range.
    #[error("{name} must be {range}, got {}", Compact(*.value))]
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: Real,
        /// The allowed range, in words.
        range: &'static str,
    },
    /// The face list is empty.
    #[error("faces is empty: select at least one triangle to spray")]
    NoFaces,
    /// A face id is not a triangle of the mesh.
    #[error("faces contains {face}, but the mesh has {count} triangles (ids 0..{count})")]
    UnknownFace {
        /// The id given.
        face: u32,
        /// Number of triangles of the mesh.
        count: usize,
    },
    /// The selected faces have no area (all degenerate).
    #[error("the selected faces have no area: every one of them is degenerate")]
    NoArea,
    /// `direction` is parallel to the patch's mean normal, so it gives no pass direction.
    #[error("direction must not be parallel to the patch's mean normal ({normal:?})")]
    DirectionAlongNormal {
        /// The patch's mean normal.
        normal: [Real; 3],
    },
    /// The spacing exceeds the width of the patch across the passes.
    #[error("spacing {} is larger than the patch, which is {} wide across the passes", Compact(*.spacing), Compact(*.width))]
    SpacingTooLarge {
        /// The spacing given.
        spacing: Real,
        /// Width of the patch across the passes.
        width: Real,
    },
    /// Too many scan planes.
    #[error("spacing {} gives {planes} scan planes across a patch {} wide; at most {max} are allowed, use a larger spacing", Compact(*.spacing), Compact(*.width), max = MAX_PLANES)]
    TooManyPlanes {
        /// The spacing.
        spacing: Real,
        /// Planes it would take.
        planes: usize,
        /// Width of the patch.
        width: Real,
    },
    /// No scan plane crosses the selected faces.
    #[error("no scan plane crosses the selected faces: the planes miss the patch")]
    PlanesMissPatch,
    /// The evaluation resolution would create too many samples.
    #[error("resolution {} would create {} evaluation samples (at most {max} allowed); use a coarser resolution, e.g. {}", Compact(*.resolution), Count(*.samples), Compact(*.suggestion), max = MAX_SAMPLES)]
    TooManySamples {
        /// The resolution used.
        resolution: Real,
        /// Samples it would create (counted as a real number: a tiny resolution makes more
        /// than any integer type holds).
        samples: Real,
        /// A resolution that fits.
        suggestion: Real,
    },
    /// So many faces that even their corners alone would be too many samples.
    #[error("{faces} triangles are selected: even unsplit, their corners would make about {samples} evaluation samples (at most {max} allowed, counting a corner once for each triangle); plan on fewer triangles, e.g. one patch", max = MAX_SAMPLES)]
    TooManyFaces {
        /// Faces selected.
        faces: usize,
        /// Samples they would create.
        samples: usize,
    },
    /// The time step would create too many trajectory samples.
    #[error("the trajectory's {} of gun-on path at timeStep {} s would take {} time samples (at most {max}); set timeStep to at least {} s, or plan fewer passes (a larger spacing or fewer faces)", Compact(*.length), Compact(*.time_step), Count(*.samples), Compact(*.suggestion), max = MAX_TIME_SAMPLES)]
    TooManyTimeSamples {
        /// The time step used.
        time_step: Real,
        /// Length of the gun-on path, mesh unit.
        length: Real,
        /// Samples it would take (a real number, as for `TooManySamples`).
        samples: Real,
        /// A time step that fits.
        suggestion: Real,
    },
    /// The speed optimiser's coating matrix would be too large.
    #[error("optimising the gun speed over {samples} evaluation samples would take more than {max} coating entries (each sample within the gun's reach of too many pieces of the passes: surfaces stacked closer than 1.5 × the standoff are coated at once); plan one side at a time (a patch), a wider spacing, or without optimising the speed", max = MAX_COATING_ENTRIES)]
    TooManyCoatingEntries {
        /// Samples the optimiser solves on.
        samples: usize,
    },
    /// The nominal speed lies outside the speed limits.
    #[error("speed {} must lie within minSpeed {} and maxSpeed {}", Compact(*.speed), Compact(*.min), Compact(*.max))]
    SpeedOutsideLimits {
        /// The speed given.
        speed: Real,
        /// Slowest speed allowed.
        min: Real,
        /// Fastest speed allowed.
        max: Real,
    },
    /// The trajectory built has a pose no robot can take (a fault of the planner if it
    /// happens: every trajectory is checked before it is deposited).
    #[error("the planned trajectory is invalid: {0} (a fault of the planner on these faces)")]
    ToolPath(#[from] crate::toolpath::ToolPathError),
}

/// Quality limits of step 7 and the spacing range searched.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct QualityLimits {
    /// Largest allowed standard deviation `E_m` of the interior thickness, file unit.
    pub max_std_dev: Option<Real>,
    /// Largest allowed error `δ_m = max |T − T̄| / T̄` in the interior (a ratio).
    pub max_error: Option<Real>,
    /// Smallest spacing tried (default `R/4`).
    pub min_spacing: Option<Real>,
    /// Largest spacing tried (default `2R`, at most the patch width).
    pub max_spacing: Option<Real>,
}

/// Everything [`plan_spray`](super::plan_spray) needs. Lengths in the mesh's unit, angles in
/// radians, times in seconds, flow rate in (mesh unit)³/s. `Default` is a painter's set-up in
/// millimetres: h 250 mm, v 400 mm/s, α 40°, Q 150 cm³/min, η 0.6, β_T 20°, b = R.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
pub struct SprayParams {
    /// Pass spacing `b` (the start of the search when quality limits are given).
    pub spacing: Real,
    /// Standoff `h` from the surface along its normal.
    pub standoff: Real,
    /// Gun speed `v` along the trajectory.
    pub speed: Real,
    /// Paint flow `Q`, (mesh unit)³/s.
    pub flow_rate: Real,
    /// Cone opening angle `α`, radians, in (0, π).
    pub cone_angle: Real,
    /// Transition threshold `β_T`, radians: straight transition up to it, arc beyond.
    pub transition_angle: Real,
    /// Transfer efficiency `η` in (0, 1] (default 0.6).
    #[serde(default = "default_efficiency")]
    pub efficiency: Real,
    /// Pass direction; default: the patch's longest extent in its mean plane.
    pub direction: Option<[Real; 3]>,
    /// Turn of the pass direction about the mean normal, radians (default 0).
    #[serde(default)]
    pub raster_angle: Real,
    /// Pass continuation past the boundary, gun on (default `R`).
    pub extension: Option<Real>,
    /// Time step of the deposition, seconds (default: `v·Δt = R/20`): bounds the work
    /// ([`MAX_TIME_SAMPLES`]) and steps the rare pieces moving along their axis; straight
    /// lateral pieces are integrated by quadrature whatever its value.
    pub time_step: Option<Real>,
    /// Distance between evaluation samples (default `R/8`): every point of the patch lies
    /// within `resolution/√2` of one, as on a square grid that far apart (see
    /// [`sample_faces`](super::sample_faces)).
    pub resolution: Option<Real>,
    /// Most evaluation samples wanted (a positive whole number): a finer resolution is
    /// coarsened until the faces' samples, counted as an upper bound, fit (see
    /// [`fit_resolution`](super::fit_resolution)); default none.
    pub sample_budget: Option<usize>,
    /// Width of the band along the boundary left out of the interior quality (default `R`).
    pub edge_exclusion: Option<Real>,
    /// Quality limits; without them the plan uses `spacing` only.
    pub quality: Option<QualityLimits>,
    /// Interior mean thickness wanted, file unit: the speeds are chosen (or the constant
    /// speed scaled) to give it, within the speed limits.
    pub target_thickness: Option<Real>,
    /// Whether the gun speed is optimised piece by piece along the passes (default true).
    #[serde(default = "default_true")]
    pub optimise_speed: bool,
    /// Slowest gun speed the plan may command (default `speed / 2`).
    pub min_speed: Option<Real>,
    /// Fastest gun speed the plan may command (default `2·speed`).
    pub max_speed: Option<Real>,
    /// Whether to try the pass direction turned by 90° and ±45° too, keeping the best
    /// quality at the chosen spacing (ties to the shorter cycle time); default false.
    #[serde(default)]
    pub best_direction: bool,
}

fn default_true() -> bool {
    true
}

fn default_efficiency() -> Real {
    0.6
}

impl Default for SprayParams {
    fn default() -> Self {
        let standoff = 250.0;
        let cone_angle = 40f64.to_radians();
        SprayParams {
            spacing: standoff * libm::tan(cone_angle / 2.0),
            standoff,
            speed: 400.0,
            flow_rate: 150.0 * 1000.0 / 60.0,
            cone_angle,
            transition_angle: 20f64.to_radians(),
            efficiency: default_efficiency(),
            direction: None,
            raster_angle: 0.0,
            extension: None,
            time_step: None,
            resolution: None,
            sample_budget: None,
            edge_exclusion: None,
            quality: None,
            target_thickness: None,
            optimise_speed: true,
            min_speed: None,
            max_speed: None,
            best_direction: false,
        }
    }
}

/// Parameters after validation, with every default resolved from `R`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resolved {
    /// Spray footprint radius `R = h·tan(α/2)`.
    pub radius: Real,
    /// Peak deposition rate `A = 2ηQ/(πR²)`, mesh unit per second.
    pub peak_rate: Real,
    /// Extension past the boundary.
    pub extension: Real,
    /// Time step, seconds.
    pub time_step: Real,
    /// Evaluation resolution.
    pub resolution: Real,
    /// Edge exclusion band.
    pub edge_exclusion: Real,
    /// The pass direction given, if any (not normalised).
    pub direction: Option<Vector3>,
    /// Slowest and fastest gun speed.
    pub speed_limits: (Real, Real),
}

fn finite(name: &'static str, value: Real) -> Result<Real, SprayError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SprayError::NotFinite { name, value })
    }
}

fn positive(name: &'static str, value: Real) -> Result<Real, SprayError> {
    if finite(name, value)? > 0.0 {
        Ok(value)
    } else {
        Err(SprayError::OutOfRange {
            name,
            value,
            range: "positive",
        })
    }
}

fn non_negative(name: &'static str, value: Real) -> Result<Real, SprayError> {
    if finite(name, value)? >= 0.0 {
        Ok(value)
    } else {
        Err(SprayError::OutOfRange {
            name,
            value,
            range: "zero or positive",
        })
    }
}

impl SprayParams {
    /// Footprint radius `R = h·tan(α/2)` (meaningful once [`validate`](Self::validate) passed).
    pub fn radius(&self) -> Real {
        self.standoff * libm::tan(self.cone_angle / 2.0)
    }

    /// Checks every parameter and resolves the defaults. Errors name the parameter.
    pub fn validate(&self) -> Result<Resolved, SprayError> {
        positive("spacing", self.spacing)?;
        positive("standoff", self.standoff)?;
        positive("speed", self.speed)?;
        positive("flowRate", self.flow_rate)?;
        let alpha = finite("coneAngle", self.cone_angle)?;
        if !(alpha > 0.0 && alpha < std::f64::consts::PI) {
            return Err(SprayError::OutOfRange {
                name: "coneAngle",
                value: alpha,
                range: "in (0, π) radians",
            });
        }
        let beta = finite("transitionAngle", self.transition_angle)?;
        if !(0.0..std::f64::consts::PI).contains(&beta) {
            return Err(SprayError::OutOfRange {
                name: "transitionAngle",
                value: beta,
                range: "in [0, π) radians",
            });
        }
        let eta = finite("efficiency", self.efficiency)?;
        if !(eta > 0.0 && eta <= 1.0) {
            return Err(SprayError::OutOfRange {
                name: "efficiency",
                value: eta,
                range: "in (0, 1]",
            });
        }
        finite("rasterAngle", self.raster_angle)?;
        let direction = match self.direction {
            Some(d) => {
                for c in d {
                    finite("direction", c)?;
                }
                let v = Vector3::from(d);
                if v.norm() == 0.0 {
                    return Err(SprayError::OutOfRange {
                        name: "direction",
                        value: 0.0,
                        range: "a non-zero vector (its length given here)",
                    });
                }
                Some(v)
            }
            None => None,
        };
        let radius = self.radius();
        let extension = match self.extension {
            Some(e) => non_negative("extension", e)?,
            None => radius,
        };
        let time_step = match self.time_step {
            Some(t) => positive("timeStep", t)?,
            None => radius / (20.0 * self.speed),
        };
        let resolution = match self.resolution {
            Some(r) => positive("resolution", r)?,
            None => radius / 8.0,
        };
        if self.sample_budget == Some(0) {
            return Err(SprayError::OutOfRange {
                name: "sampleBudget",
                value: 0.0,
                range: "a positive whole number",
            });
        }
        let edge_exclusion = match self.edge_exclusion {
            Some(e) => non_negative("edgeExclusion", e)?,
            None => radius,
        };
        if let Some(q) = &self.quality {
            if let Some(e) = q.max_std_dev {
                positive("quality.maxStdDev", e)?;
            }
            if let Some(d) = q.max_error {
                positive("quality.maxError", d)?;
            }
            if let Some(s) = q.min_spacing {
                positive("quality.minSpacing", s)?;
            }
            if let Some(s) = q.max_spacing {
                positive("quality.maxSpacing", s)?;
                if let Some(lo) = q.min_spacing {
                    if s < lo {
                        return Err(SprayError::OutOfRange {
                            name: "quality.maxSpacing",
                            value: s,
                            range: "at least quality.minSpacing",
                        });
                    }
                }
            }
        }
        if let Some(t) = self.target_thickness {
            positive("targetThickness", t)?;
        }
        let min_speed = match self.min_speed {
            Some(v) => positive("minSpeed", v)?,
            None => self.speed / 2.0,
        };
        let max_speed = match self.max_speed {
            Some(v) => positive("maxSpeed", v)?,
            None => self.speed * 2.0,
        };
        if max_speed < min_speed {
            return Err(SprayError::OutOfRange {
                name: "maxSpeed",
                value: max_speed,
                range: "at least minSpeed",
            });
        }
        if !(min_speed..=max_speed).contains(&self.speed) {
            return Err(SprayError::SpeedOutsideLimits {
                speed: self.speed,
                min: min_speed,
                max: max_speed,
            });
        }
        let peak_rate = 2.0 * eta * self.flow_rate / (std::f64::consts::PI * radius * radius);
        positive("standoff·tan(coneAngle/2)", radius)?;
        Ok(Resolved {
            radius,
            peak_rate,
            extension,
            time_step,
            resolution,
            edge_exclusion,
            direction,
            speed_limits: (min_speed, max_speed),
        })
    }

    /// Whether quality limits ask for a spacing search.
    pub fn has_limits(&self) -> bool {
        self.quality
            .is_some_and(|q| q.max_std_dev.is_some() || q.max_error.is_some())
    }
}
