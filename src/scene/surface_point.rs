//! What the whitted model needs to know about a hit: where, which way the surface
//! faces geometrically and for shading, and where textures are read.

use super::{Scene, Shape, ShapeId};
use crate::math::{Ray, Vec3};

/// A hit, resolved for shading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfacePoint {
    /// The hit point in world space, `ray.at(t)`.
    pub p: Vec3,
    /// Unit geometric normal, as the shape is wound (not turned toward the ray): for
    /// inside/outside and for offsetting new rays.
    pub ng: Vec3,
    /// Unit shading normal (interpolated vertex normals where a mesh has them), on the
    /// same side as `ng`.
    pub n: Vec3,
    /// Texture coordinates: a mesh's own, else the shape's natural parametrisation;
    /// `[0, 0]` unless they were asked for.
    pub uv: [f32; 2],
    /// Interpolated vertex colour (white where the mesh has none).
    pub color: Vec3,
    /// A mesh triangle's corners, vertex normals and the hit's barycentrics, for
    /// [`SurfacePoint::shadow_origin`].
    pub smooth: Option<([Vec3; 3], [Vec3; 3], [f32; 3])>,
}

impl SurfacePoint {
    /// Point `p` of a flat surface of unit normal `ng`, nothing interpolated across it:
    /// what [`Scene::flat_point`] finds.
    #[inline]
    pub fn flat(p: Vec3, ng: Vec3) -> SurfacePoint {
        SurfacePoint {
            p,
            ng,
            n: ng,
            uv: [0.0, 0.0],
            color: Vec3::ONE,
            smooth: None,
        }
    }

    /// Where shadow rays toward the side `side` (the geometric normal turned toward
    /// the incoming ray) start: on a smooth mesh, lifted off the flat triangle toward
    /// the surface its vertex normals describe (`terminator_point`).
    #[inline]
    pub fn shadow_origin(&self, side: Vec3) -> Vec3 {
        match self.smooth {
            Some((v, n, b)) => terminator_point(v, n, b, self.p, side),
            None => self.p,
        }
    }
}

impl Scene {
    /// A hit as a surface with nothing interpolated across it: its point and
    /// geometric normal, no texture coordinates, no vertex colour. What
    /// [`Scene::surface_point`] finds on shapes of no mesh with vertex normals or
    /// colours, when it is not asked for texture coordinates.
    #[inline]
    pub fn flat_point(&self, shape: ShapeId, ray: &Ray, t: f32) -> SurfacePoint {
        flat_point_on(&self.shape_at(shape), ray, t)
    }

    /// The shading view of a hit at distance `t` on shape `shape`, with texture
    /// coordinates if `texture_coords` (a sphere's cost two inverse trigonometric
    /// functions, and most surfaces read none).
    pub fn surface_point(
        &self,
        shape: ShapeId,
        ray: &Ray,
        t: f32,
        texture_coords: bool,
    ) -> SurfacePoint {
        let s = &self.shape_at(shape);
        let mut sp = flat_point_on(s, ray, t);
        let (p, ng) = (sp.p, sp.ng);
        match s {
            Shape::Triangle(tri) => {
                let mesh = self.mesh_at(shape);
                if !texture_coords && mesh.is_none() {
                    // A bare triangle read for lighting alone: no barycentrics needed.
                    return sp;
                }
                let b = barycentrics(tri.v, p);
                if texture_coords {
                    sp.uv = [b[1], b[2]];
                }
                if let Some(mesh) = mesh {
                    if let Some(n) = mesh.normal(b) {
                        // Vertex normals may be wound against the triangle: follow ng.
                        sp.n = if n.dot(ng) < 0.0 { -n } else { n };
                    }
                    if let Some(normals) = mesh.vertex_normals() {
                        sp.smooth = Some((tri.v, normals, b));
                    }
                    if texture_coords && let Some(uv) = mesh.texcoord(b) {
                        sp.uv = uv;
                    }
                    if let Some(c) = mesh.color(b) {
                        sp.color = c;
                    }
                }
            }
            Shape::Rectangle(_) | Shape::Sphere(_) if !texture_coords => {}
            Shape::Rectangle(r) => {
                let c = r.surface_coords(p);
                let u = if c.len_x > 0.0 { c.x / c.len_x } else { 0.0 };
                let v = if c.len_y > 0.0 { c.y / c.len_y } else { 0.0 };
                sp.uv = [u, v];
            }
            Shape::Sphere(_) => {
                // Latitude-longitude with +y up, u = 0 at -z... seam behind: a common
                // convention for spheres in y-up scenes.
                let d = ng;
                let u = 0.5 + d.x.atan2(d.z) / std::f32::consts::TAU;
                let v = 0.5 + d.y.clamp(-1.0, 1.0).asin() / std::f32::consts::PI;
                sp.uv = [u, v];
            }
        }
        sp
    }
}

/// [`Scene::flat_point`] on a shape already gathered.
#[inline]
fn flat_point_on(shape: &Shape, ray: &Ray, t: f32) -> SurfacePoint {
    let p = ray.at(t);
    SurfacePoint::flat(p, shape.normal(p))
}

/// dP/du of a triangle with texture coordinates `uv`: the solution of
/// `dp = dpdu du + dpdv dv` over two edges; `None` for degenerate coordinates.
pub fn tangent(v: [Vec3; 3], uv: [[f32; 2]; 3]) -> Option<Vec3> {
    let (dp1, dp2) = (v[1] - v[0], v[2] - v[0]);
    let (du1, dv1) = (uv[1][0] - uv[0][0], uv[1][1] - uv[0][1]);
    let (du2, dv2) = (uv[2][0] - uv[0][0], uv[2][1] - uv[0][1]);
    let det = du1 * dv2 - dv1 * du2;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let t = (dp1 * dv2 - dp2 * dv1) / det;
    t.is_finite().then_some(t)
}

impl Scene {
    /// The direction in which the texture's u grows (unnormalised) on shape `shape`:
    /// the tangent frame of normal maps. Only mesh triangles with texture coordinates
    /// and rectangles have one. Asked only by normal-mapped surfaces, so ordinary hits
    /// do not pay for it.
    pub fn dpdu(&self, shape: ShapeId) -> Option<Vec3> {
        match &self.shape_at(shape) {
            Shape::Triangle(tri) => {
                let mesh = self.mesh_at(shape)?;
                let corners = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
                let uvs = corners.map(|c| mesh.texcoord(c));
                let [Some(a), Some(b), Some(c)] = uvs else {
                    return None;
                };
                tangent(tri.v, [a, b, c])
            }
            Shape::Rectangle(r) => Some(r.v[1] - r.v[0]),
            Shape::Sphere(_) => None,
        }
    }
}

/// Barycentric coordinates of `p` (on or near the triangle's plane) for `v0 v1 v2`.
pub fn barycentrics(v: [Vec3; 3], p: Vec3) -> [f32; 3] {
    let (e1, e2, d) = (v[1] - v[0], v[2] - v[0], p - v[0]);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (dp1, dp2) = (d.dot(e1), d.dot(e2));
    let det = d11 * d22 - d12 * d12;
    if det == 0.0 || !det.is_finite() {
        return [1.0, 0.0, 0.0];
    }
    let b1 = ((d22 * dp1 - d12 * dp2) / det).clamp(0.0, 1.0);
    let b2 = ((d11 * dp2 - d12 * dp1) / det).clamp(0.0, 1.0);
    let b0 = (1.0 - b1 - b2).max(0.0);
    [b0, b1, b2]
}

/// Hanika's shadow-terminator fix ("Hacking the Shadow Terminator", Ray Tracing Gems
/// II, ch. 4): the point on the curved surface the vertex normals describe, found by
/// projecting `p` onto each vertex's tangent plane and blending the projections with
/// the barycentrics. A shadow ray leaving from there does not graze the neighbouring
/// flat triangles, so low-polygon smooth meshes have no black stair-steps where light
/// turns away.
///
/// `side` says which side of the triangle the point is seen from; vertex normals are
/// turned to it, so a mesh wound either way is lifted toward its viewer.
pub fn terminator_point(v: [Vec3; 3], n: [Vec3; 3], b: [f32; 3], p: Vec3, side: Vec3) -> Vec3 {
    let ng = side;
    let mut lifted = Vec3::ZERO;
    for i in 0..3 {
        let ni = n[i].normalize_or_zero();
        let ni = if ni.dot(ng) < 0.0 { -ni } else { ni };
        // Below the tangent plane (a convex patch): lift; above it (concave): stay.
        let d = (p - v[i]).dot(ni).min(0.0);
        lifted += (p - d * ni) * b[i];
    }
    if lifted.is_finite() { lifted } else { p }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentrics_of_the_corners_and_the_centroid() {
        let v = [Vec3::ZERO, Vec3::X, Vec3::Y];
        assert_eq!(barycentrics(v, Vec3::ZERO), [1.0, 0.0, 0.0]);
        assert_eq!(barycentrics(v, Vec3::X), [0.0, 1.0, 0.0]);
        assert_eq!(
            barycentrics(v, Vec3::new(0.25, 0.5, 0.0)),
            [0.25, 0.25, 0.5]
        );
    }

    #[test]
    fn texture_coordinates_are_computed_only_when_asked_for_and_the_rest_is_the_same() {
        use crate::scene::{MeshAttributes, Rectangle, Sphere, Triangle};
        let mut scene = Scene::default();
        scene.push_shape(
            Shape::Sphere(Sphere {
                center: Vec3::new(0.0, 1.0, 0.0),
                radius: 1.0,
            }),
            0,
        );
        scene.push_shape(
            Shape::Rectangle(Rectangle {
                v: [
                    Vec3::new(-2.0, 0.0, -2.0),
                    Vec3::new(-2.0, 0.0, 2.0),
                    Vec3::new(2.0, 0.0, 2.0),
                    Vec3::new(2.0, 0.0, -2.0),
                ],
            }),
            0,
        );
        let tri = [
            Vec3::new(-1.0, 3.0, -1.0),
            Vec3::new(1.0, 3.0, -1.0),
            Vec3::new(0.0, 3.0, 1.0),
        ];
        scene.push_shape(Shape::Triangle(Triangle { v: tri }), 0);
        scene.push_shape(Shape::Triangle(Triangle { v: tri }), 0);
        scene.meshes.push(MeshAttributes {
            first_shape: 3,
            len: 1,
            normals: vec![Vec3::Y, Vec3::new(0.0, 1.0, 0.1), Vec3::new(0.1, 1.0, 0.0)],
            normal_indices: vec![[0, 1, 2]],
            texcoords: vec![[0.0, 0.0], [1.0, 0.0], [0.5, 1.0]],
            texcoord_indices: vec![[0, 1, 2]],
            ..MeshAttributes::default()
        });
        let from_above = |x: f32, z: f32| Ray::new(Vec3::new(x, 5.0, z), -Vec3::Y);
        let hits = [
            (0, from_above(0.3, 0.4), 5.0 - 1.0 - (1.0f32 - 0.25).sqrt()),
            (1, from_above(0.5, -1.5), 5.0),
            (2, from_above(0.1, 0.2), 2.0),
            (3, from_above(0.1, 0.2), 2.0),
        ];
        for (shape, ray, t) in hits {
            let with = scene.surface_point(ShapeId::world(shape), &ray, t, true);
            let without = scene.surface_point(ShapeId::world(shape), &ray, t, false);
            assert_eq!(without.uv, [0.0, 0.0]);
            assert_ne!(with.uv, [0.0, 0.0], "shape {shape}");
            assert_eq!(
                SurfacePoint {
                    uv: with.uv,
                    ..without
                },
                with,
                "shape {shape}"
            );
        }
        // The sphere's latitude-longitude map, the mesh's own coordinates.
        let (ray, t) = (hits[0].1, hits[0].2);
        let d = scene.surface_point(ShapeId::world(0), &ray, t, true).ng;
        let u = 0.5 + d.x.atan2(d.z) / std::f32::consts::TAU;
        let v = 0.5 + d.y.clamp(-1.0, 1.0).asin() / std::f32::consts::PI;
        assert_eq!(
            scene.surface_point(ShapeId::world(0), &ray, t, true).uv,
            [u, v]
        );
        let b = barycentrics(tri, from_above(0.1, 0.2).at(2.0));
        let expected = scene.meshes[0].texcoord(0, b).unwrap();
        assert_eq!(
            scene
                .surface_point(ShapeId::world(3), &from_above(0.1, 0.2), 2.0, true)
                .uv,
            expected
        );
    }

    #[test]
    fn the_tangent_follows_u() {
        let v = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
        ];
        // u along +x over 2 units, v along +y.
        let t = tangent(v, [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).unwrap();
        assert_eq!(t, Vec3::new(2.0, 0.0, 0.0));
        // u along +y instead.
        let t = tangent(v, [[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]).unwrap();
        assert_eq!(t, Vec3::new(0.0, 3.0, 0.0));
        assert_eq!(tangent(v, [[0.0, 0.0]; 3]), None);
    }

    #[test]
    fn terminator_point_lifts_onto_a_sphere_and_leaves_flat_patches_alone() {
        // A flat triangle with its own normal at every vertex: nothing moves.
        let v = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let p = Vec3::new(0.25, 0.25, 0.0);
        assert_eq!(
            terminator_point(v, [Vec3::Z; 3], [0.5, 0.25, 0.25], p, Vec3::Z),
            p
        );
        // A triangle cut from the unit sphere, normals radial: the centroid rises
        // toward the sphere (but not past it).
        let v = [Vec3::X, Vec3::Y, Vec3::Z];
        let c = (v[0] + v[1] + v[2]) / 3.0;
        let q = terminator_point(v, v, [1.0 / 3.0; 3], c, c);
        assert!(
            q.length() > c.length() + 0.1 && q.length() <= 1.0 + 1e-6,
            "{q}"
        );
    }
}
