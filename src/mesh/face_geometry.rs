//! Per-face unit normals, areas and centroids, computed once from a [`TriMesh`].

use super::TriMesh;
use crate::math::{larger, Point3, Real, Vector3, DEGENERATE_HEIGHT_RATIO};

/// Whether `p` comes before `q` or equals it, comparing x, then y, then z (no NaN here).
#[inline(always)]
fn lexicographic_le(p: &Point3, q: &Point3) -> bool {
    p.x < q.x || (p.x == q.x && (p.y < q.y || (p.y == q.y && p.z <= q.z)))
}

/// The corners turned (keeping the winding) so that the lexicographically smallest comes
/// first. Edge vectors from that corner do not depend on where the file starts the face,
/// and reversing the winding then only negates the cross product exactly, so the
/// degeneracy test, the area and the normal (up to its sign) are the same for every vertex
/// order: a face written out and read back is judged as before. Corners that tie are equal
/// in value, and any choice among them gives a zero cross product.
#[inline(always)]
fn from_smallest_corner([a, b, c]: [Point3; 3]) -> [Point3; 3] {
    if lexicographic_le(&a, &b) && lexicographic_le(&a, &c) {
        [a, b, c]
    } else if lexicographic_le(&b, &c) {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

/// `(b − a) × (c − a)` from the smallest corner (see [`from_smallest_corner`]), and the
/// corners in that order.
#[inline(always)]
fn scaled_normal(corners: [Point3; 3]) -> (Vector3, [Point3; 3]) {
    let [a, b, c] = from_smallest_corner(corners);
    ((b - a).cross(&(c - a)), [a, b, c])
}

/// The area [`measure`] gives, bit for bit, in either winding.
#[inline(always)]
pub(crate) fn face_area(corners: [Point3; 3]) -> Real {
    0.5 * scaled_normal(corners).0.norm()
}

/// Unit normal (zero when degenerate), area and centroid of the face with corners
/// `[a, b, c]` in that winding. The normal, area and degeneracy do not depend on which
/// corner the winding starts at (see [`from_smallest_corner`]), and reversing the winding
/// negates the normal exactly.
#[inline(always)]
pub(crate) fn measure(corners: [Point3; 3]) -> (Vector3, Real, Point3) {
    let [a, b, c] = corners;
    let centroid = centroid(a, b, c);
    let (scaled, [a, b, c]) = scaled_normal(corners);
    let twice_area = scaled.norm();
    // Squared lengths are never NaN or −0, so `larger` gives exactly `f64::max`.
    let longest_sq = larger(
        larger((b - a).norm_squared(), (c - b).norm_squared()),
        (a - c).norm_squared(),
    );
    // height = 2·area / longest edge, so height < r·longest ⇔ 2·area < r·longest².
    let normal = if twice_area > DEGENERATE_HEIGHT_RATIO * longest_sq {
        scaled / twice_area
    } else {
        Vector3::zeros()
    };
    (normal, 0.5 * twice_area, centroid)
}

/// Whether the face with corners `[a, b, c]` is degenerate, as [`FaceGeometry`] counts it
/// (a height below [`DEGENERATE_HEIGHT_RATIO`] of its longest edge).
pub(crate) fn is_degenerate(corners: [Point3; 3]) -> bool {
    measure(corners).0 == Vector3::zeros()
}

/// Mean of three corners, `(a + (b + c)) / 3`: the same for `[a, c, b]`, so that turning a
/// face (which swaps corners 1 and 2) keeps its centroid bit for bit.
#[inline]
fn centroid(a: Point3, b: Point3, c: Point3) -> Point3 {
    Point3::from((a.coords + (b.coords + c.coords)) / 3.0)
}

/// Unit normal, area and centroid of every face, indexed by face id.
///
/// A degenerate face (height below [`DEGENERATE_HEIGHT_RATIO`] of its longest edge, which
/// includes zero area) has a zero normal: its direction is noise.
#[derive(Debug, Clone, PartialEq)]
pub struct FaceGeometry {
    normals: Vec<Vector3>,
    areas: Vec<Real>,
    centroids: Vec<Point3>,
    degenerate: usize,
}

impl FaceGeometry {
    /// Computes the geometry of every face of `mesh`, in its current winding.
    pub fn new(mesh: &TriMesh) -> Self {
        let n = mesh.triangle_count();
        let mut geometry = Self::with_capacity(n);
        for f in 0..n {
            geometry.push(mesh.corners(f));
        }
        geometry
    }

    /// Room for `n` faces, none computed yet.
    pub(crate) fn with_capacity(n: usize) -> Self {
        FaceGeometry {
            normals: Vec::with_capacity(n),
            areas: Vec::with_capacity(n),
            centroids: Vec::with_capacity(n),
            degenerate: 0,
        }
    }

    /// Appends the face with corners `[a, b, c]` (in its winding).
    #[inline(always)]
    pub(crate) fn push(&mut self, corners: [Point3; 3]) {
        let (normal, area, centroid) = measure(corners);
        self.degenerate += usize::from(normal == Vector3::zeros());
        self.normals.push(normal);
        self.areas.push(area);
        self.centroids.push(centroid);
    }

    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.normals.len()
    }

    /// Unit normals (zero for degenerate faces).
    pub fn normals(&self) -> &[Vector3] {
        &self.normals
    }

    /// Areas in squared model units.
    pub fn areas(&self) -> &[Real] {
        &self.areas
    }

    /// Centroids (mean of the three corners).
    pub fn centroids(&self) -> &[Point3] {
        &self.centroids
    }

    /// Whether face `f` is degenerate (has no usable normal).
    #[inline]
    pub fn is_degenerate(&self, f: usize) -> bool {
        self.normals[f] == Vector3::zeros()
    }

    /// Number of degenerate faces.
    pub fn degenerate_count(&self) -> usize {
        self.degenerate
    }

    /// Total area.
    pub fn total_area(&self) -> Real {
        self.areas.iter().sum()
    }
}
