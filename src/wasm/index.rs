//! The ray-cast and closest-point index a `Mesh` shares with its segmentations, and the ray
//! input and hit output of their `raycast` methods. Its own module so that `mesh.rs` (which
//! creates segmentations) and `segment.rs` (which casts rays) both depend on it and not on
//! each other.

use super::params::read_vector3;
use crate::math::{Compact, Point3, Real, Vector3};
use crate::mesh::{ImportedMesh, MeshIndex, RayHit};
use std::cell::OnceCell;
use std::rc::Rc;
use wasm_bindgen::prelude::*;

/// The ray-cast and closest-point index of one mesh, built by the first query that needs it
/// (a pick, a drilling query) and shared by the `Mesh` and its segmentations; it is dropped
/// with the last of them.
pub(super) type SharedIndex = Rc<OnceCell<Rc<MeshIndex>>>;

/// The index in `cell`, built from `mesh` on first use.
pub(super) fn index_of(cell: &SharedIndex, mesh: &ImportedMesh) -> Rc<MeshIndex> {
    cell.get_or_init(|| Rc::new(MeshIndex::new(&mesh.mesh)))
        .clone()
}

/// A ray read from JavaScript: `origin` and `direction` as three finite numbers each, the
/// direction not zero. Messages name the argument.
pub(super) fn read_ray(
    origin: &JsValue,
    direction: &JsValue,
) -> Result<(Point3, Vector3), JsError> {
    let finite = |value: &JsValue, name: &str| -> Result<[f64; 3], JsError> {
        let v = read_vector3(value, name)?;
        match v.iter().position(|x| !x.is_finite()) {
            Some(i) => Err(JsError::new(&format!(
                "{name}[{i}] must be a finite number, got {}",
                Compact(v[i])
            ))),
            None => Ok(v),
        }
    };
    let o = finite(origin, "origin")?;
    let d = finite(direction, "direction")?;
    let length = Vector3::from(d).norm();
    if !(length > 0.0 && length.is_finite()) {
        return Err(JsError::new(&format!(
            "direction must be a non-zero vector of finite length, got [{}, {}, {}]",
            Compact(d[0]),
            Compact(d[1]),
            Compact(d[2])
        )));
    }
    Ok((Point3::from(o), Vector3::from(d)))
}

/// `{ face, point: [x, y, z], distance }` (plus `patch` when given) as a JavaScript object.
pub(super) fn hit_to_js(hit: &RayHit, patch: Option<i32>) -> Result<JsValue, JsError> {
    #[derive(serde::Serialize)]
    struct Hit {
        face: u32,
        point: [Real; 3],
        distance: Real,
        #[serde(skip_serializing_if = "Option::is_none")]
        patch: Option<i32>,
    }
    let hit = Hit {
        face: hit.face as u32,
        point: hit.point.coords.into(),
        distance: hit.distance,
        patch,
    };
    Ok(serde_wasm_bindgen::to_value(&hit)?)
}
