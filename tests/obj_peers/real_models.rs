//! The real models: the Cornell box and spot.

use super::*;

#[test]
fn cornell_box_and_spot_load_with_their_counts() {
    let Some(root) = models() else { return };
    let cornell = load_obj(&root.join("cornell-box/CornellBox-Original.obj")).unwrap();
    assert_eq!((cornell.positions.len(), cornell.triangles.len()), (72, 36));
    assert_eq!(
        material_names(&cornell),
        [
            "leftWall",
            "rightWall",
            "floor",
            "ceiling",
            "backWall",
            "shortBox",
            "tallBox",
            "light"
        ]
    );
    let light = &cornell.materials[7];
    assert_eq!(
        (light.ke, light.kd),
        (Some(v3(17.0, 12.0, 4.0)), Some(Vec3::splat(0.78)))
    );
    assert!(cornell.triangles.iter().all(|t| t.material.is_some()));
    // `usemtl shortBox` comes before `g shortBox`, so the blocks' faces are in the
    // groups written before them; their materials are right.
    assert_eq!(
        names(&cornell),
        [
            "floor",
            "ceiling",
            "backWall",
            "rightWall",
            "leftWall",
            "shortBox",
            "light"
        ]
    );
    assert!(cornell.warnings.is_empty(), "{:?}", cornell.warnings);

    // Spot has no material library upstream (README): texture coordinates only.
    let spot = load_obj(&root.join("spot/spot_triangulated.obj")).unwrap();
    assert_eq!(
        (
            spot.positions.len(),
            spot.texcoords.len(),
            spot.triangles.len()
        ),
        (2930, 3225, 5856)
    );
    assert!(
        spot.triangles
            .iter()
            .all(|t| t.vt.is_some() && t.vn.is_none())
    );
    assert!(spot.materials.is_empty() && spot.warnings.is_empty());
}
