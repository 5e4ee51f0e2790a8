//! # skinpath
//!
//! Plans robotic surface processing of aircraft skins from triangle meshes (STL).
//!
//! Data flows one way: [`mesh`] reads STL into a welded, consistently wound [`mesh::TriMesh`]
//! with its [`mesh::FaceAdjacency`] and [`mesh::FaceGeometry`]; algorithm modules such as
//! [`segment`] take only the derived data they need; `wasm` (feature `wasm`) exposes them to
//! JavaScript and holds no logic of its own.
//!
//! ```
//! use skinpath::mesh::import_stl;
//! use skinpath::segment::{segment, SegmentParams};
//!
//! // A binary STL of one square made of two triangles.
//! let mut stl = vec![0u8; 80];
//! stl.extend_from_slice(&2u32.to_le_bytes());
//! for corners in [[0., 0., 0., 1., 0., 0., 1., 1., 0.], [0., 0., 0., 1., 1., 0., 0., 1., 0.]] {
//!     stl.extend_from_slice(&[0u8; 12]); // the file's normal, ignored
//!     corners.iter().for_each(|&c: &f32| stl.extend_from_slice(&c.to_le_bytes()));
//!     stl.extend_from_slice(&[0, 0]);
//! }
//! let imported = import_stl(&stl, &mut |_, _| {}).unwrap();
//! let seg = segment(&imported.adjacency, &imported.geometry, &SegmentParams::default()).unwrap();
//! assert_eq!((imported.report.vertices, seg.patches.len()), (4, 1));
//! ```
#![warn(missing_docs)]
#![deny(unsafe_code)]

pub mod drill;
pub mod error;
pub mod geodesic;
pub mod math;
pub mod mesh;
pub mod segment;
pub mod spray;
pub mod toolpath;

#[cfg(feature = "wasm")]
pub mod wasm;

pub use error::{Error, Result};
