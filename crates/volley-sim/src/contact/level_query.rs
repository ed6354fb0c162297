//! What the contact stage asks of a scene's level surfaces (meshes and heightfields) together:
//! is anything near this piece of path, which triangle is nearest to this point, and push a
//! sphere out of them. Surfaces are visited in scene order (meshes, then heightfields), each in
//! its fixed tree or walk order, and ties keep the first found, so answers are deterministic.

use glam::DVec3;

use super::bvh::Aabb;
use super::triangle::closest_point;
use super::{Contacts, Surface};

/// The nearest level triangle to a point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Nearest {
    /// Which surface, and which triangle or cell of it.
    pub surface: Surface,
    /// Distance from the point to the triangle (m).
    pub distance: f64,
    /// Unit vector from the triangle's closest point to the point: the contact normal (the
    /// face's normal on the face, from the edge or vertex otherwise). Zero when the point is on
    /// the triangle.
    pub normal: DVec3,
    /// The surface's restitution.
    pub restitution: f64,
}

/// Triangles to leave out of a query: those within `limit` of `point` (the ones a body touches
/// at the start of a segment it is leaving them on), and with `plane` (a unit normal `n` and
/// `n . x` of the surface a body slides on) every triangle lying in that plane, the slope's
/// other triangles, which a sliding body meets edge-on at zero depth.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Skip {
    pub point: DVec3,
    pub limit: f64,
    pub plane: Option<(DVec3, f64)>,
}

/// Whether triangle `t` lies in the plane `n . x = d` (to 1e-9 of the plane's offset).
#[inline]
pub(crate) fn in_plane(t: &[DVec3; 3], (n, d): (DVec3, f64)) -> bool {
    let tol = 1e-9 * (1.0 + d.abs());
    t.iter().all(|c| (n.dot(*c) - d).abs() <= tol)
}

impl Skip {
    /// The cheap half: in the sliding plane.
    #[inline]
    fn in_plane(&self, t: &[DVec3; 3]) -> bool {
        self.plane.is_some_and(|p| in_plane(t, p))
    }

    /// The other half: touched at the start.
    #[inline]
    fn touched(&self, t: &[DVec3; 3]) -> bool {
        (closest_point(self.point, t[0], t[1], t[2]).0 - self.point).length() <= self.limit
    }
}

impl Contacts {
    /// Whether the scene has meshes or heightfields.
    #[inline]
    pub(crate) fn has_levels(&self) -> bool {
        !self.meshes.is_empty() || !self.heightfields.is_empty()
    }

    /// Whether `query` overlaps any level surface's world box: the cheap gate of the hot loop.
    #[inline]
    pub(crate) fn levels_overlap(&self, query: &Aabb) -> bool {
        self.meshes.iter().any(|m| m.bounds().overlaps(query))
            || self.heightfields.iter().any(|h| h.bounds().overlaps(query))
    }
}

/// The level triangles the contact stage asks about: every surface of the scene through its
/// hierarchy or walk ([`Contacts`]), or the few gathered once for a body's step
/// ([`Candidates`]); the queries are the same on both.
pub(crate) trait LevelTriangles {
    /// Calls `f(surface, restitution, corners)` for every level triangle that may lie within
    /// `radius` of `center` (the broad phase's candidates), until it returns `true`.
    fn any_triangle<F: FnMut(Surface, f64, &[DVec3; 3]) -> bool>(
        &self,
        center: DVec3,
        radius: f64,
        f: F,
    ) -> bool;

    /// Whether every level triangle that may come within `radius` of `center` lies in the
    /// plane `n . x = d` (a body sliding on a flat part of a level: nothing else to meet).
    fn only_plane(&self, center: DVec3, radius: f64, plane: (DVec3, f64)) -> bool {
        !self.any_triangle(center, radius, |_, _, t| !in_plane(t, plane))
    }

    /// Whether some level triangle (not skipped) comes within `radius` of `center`.
    fn level_near(&self, center: DVec3, radius: f64, skip: Option<Skip>) -> bool {
        self.any_triangle(center, radius, |_, _, t| {
            if skip.is_some_and(|s| s.in_plane(t)) {
                return false;
            }
            let q = closest_point(center, t[0], t[1], t[2]).0;
            (q - center).length() <= radius && !skip.is_some_and(|s| s.touched(t))
        })
    }

    /// The nearest level triangle (not skipped) within `reach` of `p`, if any.
    fn level_nearest(&self, p: DVec3, reach: f64, skip: Option<Skip>) -> Option<Nearest> {
        let mut best: Option<Nearest> = None;
        self.any_triangle(p, reach, |surface, restitution, t| {
            if skip.is_some_and(|s| s.in_plane(t)) {
                return false;
            }
            let q = closest_point(p, t[0], t[1], t[2]).0;
            let d = (p - q).length();
            if d <= reach
                && best.is_none_or(|b| d < b.distance)
                && !skip.is_some_and(|s| s.touched(t))
            {
                best = Some(Nearest {
                    surface,
                    distance: d,
                    normal: (p - q).normalize_or_zero(),
                    restitution,
                });
            }
            false
        });
        best
    }

    /// Every level triangle within `reach` of `p`, in visit order, to `f`.
    fn level_touching(&self, p: DVec3, reach: f64, mut f: impl FnMut(Nearest)) {
        self.any_triangle(p, reach, |surface, restitution, t| {
            let q = closest_point(p, t[0], t[1], t[2]).0;
            let d = (p - q).length();
            if d <= reach {
                f(Nearest {
                    surface,
                    distance: d,
                    normal: (p - q).normalize_or_zero(),
                    restitution,
                });
            }
            false
        });
    }

    /// Pushes a sphere of radius `r` at `p` out of every level triangle it overlaps, along each
    /// one's contact normal, in up to [`DEPENETRATION_PASSES`] passes (a concave corner needs
    /// one per face). Returns the last normal it pushed along, if any.
    fn level_depenetrate(&self, p: &mut DVec3, r: f64) -> Option<DVec3> {
        let mut pushed = None;
        for _ in 0..DEPENETRATION_PASSES {
            let Some(n) = self.level_nearest(*p, r, None) else {
                break;
            };
            if n.distance >= r || n.normal == DVec3::ZERO {
                break;
            }
            *p += (r - n.distance) * n.normal;
            pushed = Some(n.normal);
        }
        pushed
    }
}

impl LevelTriangles for Contacts {
    /// Calls `f(surface, restitution, corners)` for every level triangle that may lie within
    /// `radius` of `center` (the broad phase's candidates), until it returns `true`.
    #[inline]
    fn any_triangle<F: FnMut(Surface, f64, &[DVec3; 3]) -> bool>(
        &self,
        center: DVec3,
        radius: f64,
        mut f: F,
    ) -> bool {
        let query = Aabb::of_segment(center, center, radius);
        for (k, m) in self.meshes.iter().enumerate() {
            let hit = m.bvh.any(&query, |id, t| {
                f(
                    Surface::Mesh {
                        surface: k as u32,
                        triangle: id,
                    },
                    m.restitution,
                    t,
                )
            });
            if hit {
                return true;
            }
        }
        for (k, h) in self.heightfields.iter().enumerate() {
            if !h.bounds().overlaps(&query) {
                continue;
            }
            let hit = h.index.any(&h.grid, center, radius, |id, t| {
                f(
                    Surface::Heightfield {
                        surface: k as u32,
                        cell: id / 2,
                        triangle: (id % 2) as u8,
                    },
                    h.restitution,
                    t,
                )
            });
            if hit {
                return true;
            }
        }
        false
    }
}

/// Most triangles gathered for one body's step ([`Candidates`]); a step near more falls back
/// to the hierarchy for every query.
pub(crate) const MAX_CANDIDATES: usize = 48;

#[derive(Clone, Copy)]
struct Candidate {
    corners: [DVec3; 3],
    bounds: Aabb,
    surface: Surface,
    restitution: f64,
}

thread_local! {
    /// Each thread's candidate list, lent to one [`Candidates`] at a time and given back when
    /// it drops: capacity only, cleared at each gather, so no answer depends on it. (A list
    /// held in the struct, `[Candidate; MAX_CANDIDATES]`, was 7 KB to fill and to move for
    /// every gather: a quarter of a resting body's contact cost on a mesh.)
    static LISTS: std::cell::Cell<Vec<Candidate>> = const { std::cell::Cell::new(Vec::new()) };
}

/// The level triangles near one body's step, gathered from the hierarchies and walks once
/// (every triangle whose box meets `bounds`), so the step's many queries test a handful of
/// triangles instead of walking the trees each time. A query whose box leaves `bounds` (the
/// path after a bounce) goes to the trees, with the same answers.
pub(crate) struct Candidates<'a> {
    contacts: &'a Contacts,
    bounds: Aabb,
    list: Vec<Candidate>,
    complete: bool,
}

impl Drop for Candidates<'_> {
    fn drop(&mut self) {
        LISTS.set(std::mem::take(&mut self.list));
    }
}

impl<'a> Candidates<'a> {
    /// The triangles of `contacts` whose boxes meet `bounds`, in the trees' order.
    pub(crate) fn gather(contacts: &'a Contacts, bounds: Aabb) -> Candidates<'a> {
        let mut list = LISTS.take();
        list.clear();
        list.reserve(MAX_CANDIDATES);
        let mut c = Candidates {
            contacts,
            bounds,
            list,
            complete: true,
        };
        let center = 0.5 * (bounds.min + bounds.max);
        let radius = 0.5 * (bounds.max - bounds.min).length();
        if !center.is_finite() || !radius.is_finite() {
            c.complete = false;
            return c;
        }
        contacts.any_triangle(center, radius, |surface, restitution, t| {
            let tb = Aabb::EMPTY.with(t[0]).with(t[1]).with(t[2]);
            if !tb.overlaps(&bounds) {
                return false;
            }
            if c.list.len() == MAX_CANDIDATES {
                c.complete = false;
                return true;
            }
            c.list.push(Candidate {
                corners: *t,
                bounds: tb,
                surface,
                restitution,
            });
            false
        });
        c
    }
}

impl LevelTriangles for Candidates<'_> {
    #[inline]
    fn any_triangle<F: FnMut(Surface, f64, &[DVec3; 3]) -> bool>(
        &self,
        center: DVec3,
        radius: f64,
        mut f: F,
    ) -> bool {
        let query = Aabb::of_segment(center, center, radius);
        let inside = (query.min.cmpge(self.bounds.min) & query.max.cmple(self.bounds.max)).all();
        if !(self.complete && inside) {
            return self.contacts.any_triangle(center, radius, f);
        }
        for c in &self.list {
            if c.bounds.overlaps(&query) && f(c.surface, c.restitution, &c.corners) {
                return true;
            }
        }
        false
    }
}

/// Passes of [`LevelTriangles::level_depenetrate`]. In a corner each pass pushes out of the nearest
/// face, which can push into the other by the cosine of their normals' angle; two faces at
/// 80 degrees converge by a factor of 0.03 a pair of passes, so 16 passes leave rounding.
pub(crate) const DEPENETRATION_PASSES: usize = 16;
