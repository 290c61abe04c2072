//! Polygons to triangles. Convex polygons become the fan `(1, k, k+1)`, so triangle
//! numbers match other renderers'; concave ones are ear-clipped in their best-fit
//! (Newell) plane. Every polygon of `n` corners gives exactly `n - 2` triangles (some
//! may have zero area when corners are collinear or repeated), wound as the polygon is.

use crate::math::Vec3;

/// Polygons with more corners than this are fanned rather than ear-clipped: clipping
/// costs up to n² point tests per ear found, and no real model has such faces.
pub const MAX_EAR_CLIPPED_CORNERS: usize = 1024;

/// How a polygon was split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Convex (or flat, with no area to lose): the fan `(1, k, k+1)`.
    Fan,
    /// Concave: ear clipping.
    EarClipped,
    /// Concave but self-intersecting or too large to clip: a fan, which may cover
    /// area outside the polygon.
    FanFallback,
}

/// Scratch space reused from one polygon to the next.
#[derive(Default)]
pub struct Triangulator {
    plane: Vec<[f64; 2]>,
    ring: Vec<u32>,
}

impl Triangulator {
    /// Appends the `n - 2` triangles of the polygon with the given corners to `out`, as
    /// indices into `corners`.
    pub fn triangulate(&mut self, corners: &[Vec3], out: &mut Vec<[u32; 3]>) -> Method {
        let n = corners.len();
        if n < 3 {
            return Method::Fan;
        }
        if n == 3 || !self.project(corners) || self.is_convex() {
            fan(0..n as u32, out);
            return Method::Fan;
        }
        if n > MAX_EAR_CLIPPED_CORNERS {
            fan(0..n as u32, out);
            return Method::FanFallback;
        }
        self.ring.clear();
        self.ring.extend(0..n as u32);
        if self.clip_ears(out) {
            Method::EarClipped
        } else {
            fan(self.ring.iter().copied(), out);
            Method::FanFallback
        }
    }

    /// Projects the corners onto the plane of their Newell normal, counter-clockwise,
    /// relative to the first corner (large coordinates keep their precision). False
    /// when the polygon has no area to project.
    fn project(&mut self, corners: &[Vec3]) -> bool {
        let origin = corners[0];
        let p = |i: usize| {
            let d = corners[i] - origin;
            [d.x as f64, d.y as f64, d.z as f64]
        };
        let mut normal = [0.0f64; 3];
        for i in 0..corners.len() {
            let (a, b) = (p(i), p((i + 1) % corners.len()));
            normal[0] += (a[1] - b[1]) * (a[2] + b[2]);
            normal[1] += (a[2] - b[2]) * (a[0] + b[0]);
            normal[2] += (a[0] - b[0]) * (a[1] + b[1]);
        }
        let abs = normal.map(f64::abs);
        if !abs.iter().all(|c| c.is_finite()) || abs.iter().all(|&c| c == 0.0) {
            return false;
        }
        // Drop the dominant axis; each component of the Newell normal is twice the
        // signed area in the other two axes, so its sign says which order is CCW.
        let axis = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        let (u, v) = [(1, 2), (2, 0), (0, 1)][axis];
        let (u, v) = if normal[axis] > 0.0 { (u, v) } else { (v, u) };
        self.plane.clear();
        self.plane
            .extend((0..corners.len()).map(|i| [p(i)[u], p(i)[v]]));
        true
    }

    /// Convex: no right turn, and the edges turn around once (a pentagram turns only
    /// left but twice around). Collinear and repeated corners are allowed.
    fn is_convex(&self) -> bool {
        let pts = &self.plane;
        let n = pts.len();
        let mut sign_changes = [0u32; 2];
        let mut last_sign = [0.0f64; 2];
        for i in 0..n {
            let (a, b, c) = (pts[i], pts[(i + 1) % n], pts[(i + 2) % n]);
            if orient(a, b, c) < 0.0 {
                return false;
            }
            let edge = [b[0] - a[0], b[1] - a[1]];
            for k in 0..2 {
                if edge[k] != 0.0 {
                    let sign = edge[k].signum();
                    if last_sign[k] != 0.0 && sign != last_sign[k] {
                        sign_changes[k] += 1;
                    }
                    last_sign[k] = sign;
                }
            }
        }
        // Closing the loop can add one more change per axis.
        sign_changes.iter().all(|&c| c <= 2)
    }

    /// Clips ears until three corners remain; false when no ear can be found (a
    /// self-intersecting polygon) or the work budget runs out, leaving `ring` as is.
    fn clip_ears(&mut self, out: &mut Vec<[u32; 3]>) -> bool {
        let pts = &self.plane;
        let ring = &mut self.ring;
        let n = ring.len();
        let mut budget = 16 * n * n + 1024;
        let mut i = 0;
        while ring.len() > 3 {
            let m = ring.len();
            let mut clipped = false;
            // First proper ears; only when there is none, zero-area corners (collinear
            // or repeated), which lose no area.
            'passes: for allow_flat in [false, true] {
                for step in 0..m {
                    let at = (i + step) % m;
                    let (prev, cur, next) = (ring[(at + m - 1) % m], ring[at], ring[(at + 1) % m]);
                    let (a, b, c) = (pts[prev as usize], pts[cur as usize], pts[next as usize]);
                    let turn = orient(a, b, c);
                    let is_ear = if allow_flat {
                        turn == 0.0
                    } else {
                        if turn <= 0.0 {
                            continue;
                        }
                        budget = match budget.checked_sub(m) {
                            Some(left) => left,
                            None => return false,
                        };
                        !ring.iter().any(|&k| {
                            k != prev
                                && k != cur
                                && k != next
                                && inside_or_on(a, b, c, pts[k as usize])
                        })
                    };
                    if is_ear {
                        out.push([prev, cur, next]);
                        ring.remove(at);
                        i = if at == 0 { 0 } else { at - 1 };
                        clipped = true;
                        break 'passes;
                    }
                }
            }
            if !clipped {
                return false;
            }
        }
        out.push([ring[0], ring[1], ring[2]]);
        true
    }
}

/// Twice the signed area of the triangle `a b c`: positive when counter-clockwise.
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether `p` lies in the counter-clockwise triangle `a b c` or on its edges, but is
/// none of its corners (a repeated corner does not block an ear).
fn inside_or_on(a: [f64; 2], b: [f64; 2], c: [f64; 2], p: [f64; 2]) -> bool {
    p != a
        && p != b
        && p != c
        && orient(a, b, p) >= 0.0
        && orient(b, c, p) >= 0.0
        && orient(c, a, p) >= 0.0
}

fn fan(ring: impl IntoIterator<Item = u32>, out: &mut Vec<[u32; 3]>) {
    let mut ring = ring.into_iter();
    let (Some(first), Some(mut last)) = (ring.next(), ring.next()) else {
        return;
    };
    for k in ring {
        out.push([first, last, k]);
        last = k;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::cross;
    use proptest::prelude::*;

    fn split(points: &[[f32; 3]]) -> (Method, Vec<[u32; 3]>) {
        let corners: Vec<Vec3> = points.iter().map(|&p| Vec3::from_array(p)).collect();
        let mut out = Vec::new();
        let method = Triangulator::default().triangulate(&corners, &mut out);
        (method, out)
    }

    /// Area of a polygon in the z = 0 plane (shoelace), positive when counter-clockwise.
    fn area_2d(points: &[[f32; 3]]) -> f64 {
        let n = points.len();
        (0..n)
            .map(|i| {
                let (a, b) = (points[i], points[(i + 1) % n]);
                a[0] as f64 * b[1] as f64 - b[0] as f64 * a[1] as f64
            })
            .sum::<f64>()
            / 2.0
    }

    fn triangles_area(points: &[[f32; 3]], triangles: &[[u32; 3]]) -> f64 {
        triangles
            .iter()
            .map(|t| area_2d(&t.map(|i| points[i as usize])))
            .sum()
    }

    /// Even-odd test of a point against a polygon in the z = 0 plane.
    fn contains(points: &[[f32; 3]], p: [f64; 2]) -> bool {
        let n = points.len();
        let mut inside = false;
        for i in 0..n {
            let (a, b) = (points[i], points[(i + n - 1) % n]);
            let (ax, ay, bx, by) = (a[0] as f64, a[1] as f64, b[0] as f64, b[1] as f64);
            if (ay > p[1]) != (by > p[1]) && p[0] < (bx - ax) * (p[1] - ay) / (by - ay) + ax {
                inside = !inside;
            }
        }
        inside
    }

    #[test]
    fn convex_polygons_fan_from_the_first_corner() {
        let pentagon = [
            [0., 0., 0.],
            [2., 0., 0.],
            [3., 1., 0.],
            [1., 2., 0.],
            [-1., 1., 0.],
        ];
        let (method, triangles) = split(&pentagon);
        assert_eq!(method, Method::Fan);
        assert_eq!(triangles, [[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        // Clockwise as seen from +z is just as convex.
        let mut reversed = pentagon;
        reversed.reverse();
        assert_eq!(split(&reversed).0, Method::Fan);
        // Collinear corners keep the fan (a quad with a midpoint on one side).
        let with_midpoint = [
            [0., 0., 0.],
            [1., 0., 0.],
            [2., 0., 0.],
            [2., 1., 0.],
            [0., 1., 0.],
        ];
        assert_eq!(split(&with_midpoint).0, Method::Fan);
    }

    #[test]
    fn concave_polygons_are_ear_clipped_without_losing_area() {
        // An L: the fan from corner 0 would cover the notch.
        let l_shape = [
            [1., 1., 0.],
            [2., 1., 0.],
            [2., 2., 0.],
            [0., 2., 0.],
            [0., 0., 0.],
            [1., 0., 0.],
        ];
        let (method, triangles) = split(&l_shape);
        assert_eq!(method, Method::EarClipped);
        assert_eq!(triangles.len(), 4);
        assert_eq!(triangles_area(&l_shape, &triangles), 3.0);
        for t in &triangles {
            assert!(
                area_2d(&t.map(|i| l_shape[i as usize])) >= 0.0,
                "{t:?} flips"
            );
        }
    }

    #[test]
    fn vertical_and_tilted_concave_polygons_clip_in_their_own_plane() {
        // The L in the x = 5 plane, wound either way.
        let l_yz: Vec<[f32; 3]> = [[1., 1.], [2., 1.], [2., 2.], [0., 2.], [0., 0.], [1., 0.]]
            .iter()
            .map(|&[a, b]| [5.0, a, b])
            .collect();
        for points in [l_yz.clone(), l_yz.iter().rev().copied().collect()] {
            let (method, triangles) = split(&points);
            assert_eq!(method, Method::EarClipped);
            let corners: Vec<Vec3> = points.iter().map(|&p| Vec3::from_array(p)).collect();
            let area: f32 = triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| corners[i as usize]);
                    cross(b - a, c - a).x / 2.0
                })
                .sum();
            assert_eq!(area.abs(), 3.0);
            assert!(triangles.iter().all(|t| {
                let [a, b, c] = t.map(|i| corners[i as usize]);
                cross(b - a, c - a).x * area >= 0.0
            }));
        }
    }

    #[test]
    fn degenerate_and_self_intersecting_polygons_fall_back_to_a_fan() {
        // All on a line: no area, any split is as good.
        let line = [[0., 0., 0.], [1., 0., 0.], [2., 0., 0.], [3., 0., 0.]];
        assert_eq!(split(&line), (Method::Fan, vec![[0, 1, 2], [0, 2, 3]]));
        // A pentagram turns left at every corner but winds twice.
        let star: Vec<[f32; 3]> = (0..5)
            .map(|k| {
                let a = std::f32::consts::TAU * (2 * k) as f32 / 5.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let (method, triangles) = split(&star);
        assert_ne!(method, Method::Fan);
        assert_eq!(triangles.len(), 3);
        // A bow tie.
        let bow = [[0., 0., 0.], [1., 1., 0.], [1., 0., 0.], [0., 1., 0.]];
        assert_eq!(split(&bow).1.len(), 2);
    }

    proptest! {
        #![proptest_config(ProptestConfig { rng_seed: proptest::test_runner::RngSeed::Fixed(7), ..ProptestConfig::default() })]

        /// Star-shaped polygons around the origin (simple, often concave): the triangles
        /// cover exactly the polygon's area and their centroids lie inside it.
        #[test]
        fn star_shaped_polygons_keep_their_area(
            radii in prop::collection::vec(1u8..=10, 3..40),
        ) {
            let n = radii.len();
            let points: Vec<[f32; 3]> = radii
                .iter()
                .enumerate()
                .map(|(k, &r)| {
                    let a = std::f64::consts::TAU * k as f64 / n as f64;
                    [(r as f64 * a.cos()) as f32, (r as f64 * a.sin()) as f32, 0.0]
                })
                .collect();
            let (_, triangles) = split(&points);
            prop_assert_eq!(triangles.len(), n - 2);
            let expected = area_2d(&points);
            let got = triangles_area(&points, &triangles);
            prop_assert!((got - expected).abs() <= 1e-9 * expected.abs().max(1.0), "{} vs {}", got, expected);
            for t in &triangles {
                let c = t.map(|i| points[i as usize]);
                let signed = area_2d(&c);
                prop_assert!(signed >= 0.0);
                if signed > 1e-6 {
                    let centroid = [
                        (c[0][0] + c[1][0] + c[2][0]) as f64 / 3.0,
                        (c[0][1] + c[1][1] + c[2][1]) as f64 / 3.0,
                    ];
                    prop_assert!(contains(&points, centroid), "{:?} is outside", t);
                }
            }
        }

        /// Any corners at all: n - 2 triangles of corner indices, quickly.
        #[test]
        fn any_polygon_gives_n_minus_2_triangles(
            corners in prop::collection::vec((-4i8..4, -4i8..4, -1i8..1), 0..30),
        ) {
            let points: Vec<[f32; 3]> =
                corners.iter().map(|&(x, y, z)| [x as f32, y as f32, z as f32]).collect();
            let (_, triangles) = split(&points);
            prop_assert_eq!(triangles.len(), points.len().saturating_sub(2));
            prop_assert!(triangles.iter().flatten().all(|&i| (i as usize) < points.len()));
        }
    }
}
