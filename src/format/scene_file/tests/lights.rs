//! Lights of every type, and glowing objects as area lights in their group.

use super::*;
use crate::scene::{Falloff, LightKind};

#[test]
fn lights_of_every_type() {
    let f = scene(
        "[[light]]\ntype = \"point\"\nposition = [1, 2, 3]\ncolor = [1, 0.5, 0]\nintensity = 2\n\
         falloff = \"inverse_square\"\n\
         [[light]]\ntype = \"directional\"\ndirection = [0, -2, 0]\n\
         [[light]]\ntype = \"spot\"\nposition = [0, 5, 0]\nat = [0, 0, 0]\nangle = 60\n\
         falloff_angle = 30\n\
         [[light]]\ntype = \"quad\"\ncorner = [0, 4, 0]\nedge1 = [2, 0, 0]\nedge2 = [0, 0, 2]\n\
         samples = 9\n\
         [[light]]\ntype = \"disk\"\ncenter = [0, 3, 0]\nradius = 0.5\n\
         [[light]]\nname = \"bulb\"\ntype = \"sphere\"\ncenter = [1, 1, 1]\nradius = 0.25\n",
    );
    let l = &f.scene.lights;
    assert_eq!(l.len(), 6);
    assert_eq!(
        (
            l[0].position,
            l[0].color,
            l[0].intensity,
            l[0].falloff,
            &l[0].kind
        ),
        (
            v(1.0, 2.0, 3.0),
            v(1.0, 0.5, 0.0),
            2.0,
            Falloff::InverseSquare,
            &LightKind::Point
        )
    );
    assert_eq!(
        l[1].kind,
        LightKind::Directional {
            direction: -Vec3::Y
        }
    );
    let LightKind::Spot {
        direction,
        cos_inner,
        cos_outer,
        ..
    } = l[2].kind
    else {
        panic!()
    };
    assert_eq!(direction, -Vec3::Y);
    assert!((cos_outer - 0.5).abs() < 1e-6 && (cos_inner - 0.75f32.sqrt()).abs() < 1e-6);
    assert_eq!(l[3].position, v(1.0, 4.0, 1.0));
    assert_eq!(
        l[3].kind,
        LightKind::Quad {
            u: v(2.0, 0.0, 0.0),
            v: v(0.0, 0.0, 2.0)
        }
    );
    assert_eq!(l[3].samples, 9);
    assert_eq!(
        l[4].kind,
        LightKind::Disk {
            normal: -Vec3::Y,
            radius: 0.5
        }
    );
    assert_eq!(l[4].samples, DEFAULT_AREA_SAMPLES);
    assert_eq!(l[5].kind, LightKind::Sphere { radius: 0.25 });
    assert_eq!(f.scene.group("bulb").unwrap().lights, [5]);
}

#[test]
fn glowing_objects_are_area_lights_in_their_group() {
    let f = scene(
        "[[material]]\nname = \"lamp\"\nemission = [4, 4, 3]\n\
         [[object]]\nname = \"panel\"\ntype = \"quad\"\ncorner = [0, 2, 0]\nedge1 = [0, 0, 1]\n\
         edge2 = [3, 0, 0]\nmaterial = \"lamp\"\nsamples = 4\n\
         [[object]]\nname = \"ball\"\ntype = \"sphere\"\ncenter = [0, 1, 0]\nradius = 0.5\n\
         material = \"lamp\"\n",
    );
    // The quad became two triangles, sampled by area (1.5 each).
    assert_eq!(f.scene.shapes.len(), 3);
    let LightKind::Mesh { shapes, cdf, area } = &f.scene.lights[0].kind else {
        panic!()
    };
    assert_eq!(
        (shapes.as_slice(), cdf.as_slice(), *area),
        (
            &[
                crate::scene::ShapeId::world(0),
                crate::scene::ShapeId::world(1)
            ][..],
            &[0.5, 1.0][..],
            3.0
        )
    );
    assert_eq!(f.scene.lights[0].samples, 4);
    assert_eq!(f.scene.lights[1].kind, LightKind::Sphere { radius: 0.5 });
    assert_eq!(f.scene.lights[1].color, v(4.0, 4.0, 3.0));
    let panel = f.scene.group("panel").unwrap();
    assert_eq!(
        (panel.shapes.as_slice(), panel.lights.as_slice()),
        (&[0, 1][..], &[0][..])
    );
    assert_eq!(f.scene.group("ball").unwrap().lights, [1]);
}

#[test]
fn a_spot_edge_of_smooth_cosine_fades_as_cycles_spots_do() {
    let f = scene(
        "[[light]]\ntype = \"spot\"\nposition = [0, 5, 0]\nat = [0, 0, 0]\nangle = 60\n\
         inner_angle = 30\nedge = \"smooth_cosine\"\nfalloff = \"inverse_square\"\n",
    );
    let LightKind::Spot {
        cos_inner,
        cos_outer,
        edge,
        ..
    } = f.scene.lights[0].kind
    else {
        panic!("a spot light")
    };
    assert_eq!(edge, crate::scene::ConeEdge::SmoothCosine);
    // Inside the inner cone only the cosine remains; midway the smoothstep is 1/2.
    let at = |deg: f32| edge.at(cos_outer, cos_inner, deg.to_radians().cos());
    assert_eq!(at(0.0), 1.0);
    assert!((at(20.0) - 20f32.to_radians().cos()).abs() < 1e-6);
    let mid = (cos_outer + cos_inner) / 2.0;
    assert!((edge.at(cos_outer, cos_inner, mid) - 0.5 * mid).abs() < 1e-6);
    assert_eq!(at(61.0), 0.0);
    let bad = Folder::new().error(
        "[[light]]\ntype = \"spot\"\nposition = [0, 5, 0]\nat = [0, 0, 0]\nedge = \"hard\"\n",
    );
    assert!(
        bad.contains("expected edge \"smooth\" or \"smooth_cosine\""),
        "{bad}"
    );
}
