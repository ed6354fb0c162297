//! The closest point of a triangle to a point, and which feature it lies on.
//!
//! A sphere of radius `r` centred at `p` touches a triangle exactly when the distance from `p`
//! to the closest point of the triangle is `r`. Splitting that closest point by the Voronoi
//! region of `p` is the sphere-triangle test of Ericson, *Real-Time Collision Detection* (2005),
//! section 5.1.5 (`ClosestPtPointTriangle`): the face's region (the sphere meets the face
//! plane), the three edges' regions (it meets an edge's capsule) and the three vertices'
//! regions (it meets a vertex's sphere). The contact normal is `(p - q) / |p - q|` in every
//! region: the face normal on the face, the direction from the edge or the vertex otherwise.

use glam::DVec3;

/// The part of a triangle a closest point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// Inside the face.
    Face,
    /// On edge `k`, from vertex `k` to vertex `(k + 1) % 3`.
    Edge(u8),
    /// On vertex `k`.
    Vertex(u8),
}

/// The closest point of triangle `(a, b, c)` to `p`, and its feature (Ericson 5.1.5).
///
/// Exact arithmetic would give the same point from any vertex order; in floating point the
/// result depends on it, so callers pass the triangle's stored order (deterministic).
#[inline]
pub fn closest_point(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, Feature) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(0));
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + v * ab, Feature::Edge(0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + w * ac, Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + w * (c - b), Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    (a + ab * v + ac * w, Feature::Face)
}

/// Whether a triangle is degenerate: its area is below `1e-12` of its longest edge squared
/// (a sliver or a point). Such triangles have no face normal; the readers skip them and count
/// them ([`crate::contact::MeshGeometry::degenerate`]).
pub fn is_degenerate(a: DVec3, b: DVec3, c: DVec3) -> bool {
    let (ab, ac, bc) = (b - a, c - a, c - b);
    let longest = ab
        .length_squared()
        .max(ac.length_squared())
        .max(bc.length_squared());
    let twice_area = ab.cross(ac).length();
    let fair = twice_area.is_finite() && twice_area > 1e-12 * longest;
    !fair
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: DVec3 = DVec3::new(0.0, 0.0, 0.0);
    const B: DVec3 = DVec3::new(2.0, 0.0, 0.0);
    const C: DVec3 = DVec3::new(0.0, 2.0, 0.0);

    #[test]
    fn a_point_above_the_face_projects_onto_it() {
        let (q, f) = closest_point(DVec3::new(0.5, 0.5, 3.0), A, B, C);
        assert_eq!((q, f), (DVec3::new(0.5, 0.5, 0.0), Feature::Face));
    }

    #[test]
    fn every_vertex_and_edge_region_is_named() {
        let p = |x, y| closest_point(DVec3::new(x, y, 1.0), A, B, C);
        assert_eq!(p(-1.0, -1.0), (A, Feature::Vertex(0)));
        assert_eq!(p(3.0, -1.0), (B, Feature::Vertex(1)));
        assert_eq!(p(-1.0, 3.0), (C, Feature::Vertex(2)));
        assert_eq!(p(1.0, -1.0), (DVec3::new(1.0, 0.0, 0.0), Feature::Edge(0)));
        assert_eq!(p(2.0, 2.0), (DVec3::new(1.0, 1.0, 0.0), Feature::Edge(1)));
        assert_eq!(p(-1.0, 1.0), (DVec3::new(0.0, 1.0, 0.0), Feature::Edge(2)));
    }

    #[test]
    fn slivers_and_points_are_degenerate_and_a_fair_triangle_is_not() {
        assert!(!is_degenerate(A, B, C));
        assert!(is_degenerate(A, B, DVec3::new(1.0, 0.0, 0.0)));
        assert!(is_degenerate(A, A, A));
        assert!(is_degenerate(A, B, DVec3::new(f64::NAN, 0.0, 0.0)));
    }
}
