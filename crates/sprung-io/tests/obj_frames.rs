//! OBJ frames as another reader (tobj, the OBJ reader the mesh loader also
//! uses) sees them: every vertex, a unit normal per vertex that is the
//! smooth normal of the surface, faces in a smoothing group that point at
//! their normals, and ropes as lines.

mod common;

use sprung::{build, IntegratorKind, Vec3, World};
use sprung_io::export::{write_frame, FrameFormat};

#[test]
fn obj_frames_carry_smooth_vertex_normals() {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let ball = build::icosphere(0.5, 2, build::SurfaceSprings::default())
        .expect("sphere")
        .with_stiffness(100.0);
    world.add_body("ball", ball).expect("ball");
    let rope = build::rope(4, 1.0).expect("rope").with_stiffness(100.0);
    world.add_body("rope", rope).expect("rope");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = write_frame(dir.path(), 0, &world, FrameFormat::Obj).expect("frame");
    let text = std::fs::read_to_string(&path).expect("read");
    assert!(
        text.contains("\no ball\ns 1\nf "),
        "smoothing group 1 for the surface"
    );
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: false,
        ignore_lines: false,
        ignore_points: true,
    };
    let (models, _) = tobj::load_obj(&path, &options).expect("tobj reads it");
    let ball = models
        .iter()
        .find(|m| m.name == "ball")
        .expect("ball")
        .mesh
        .clone();
    // tobj keeps the vertices a model uses: the ball's 162.
    assert_eq!(ball.positions.len(), 3 * 162);
    assert_eq!(
        ball.indices.len(),
        3 * 320,
        "the 320 triangles of a 2-level icosphere"
    );
    assert_eq!(
        ball.normal_indices.len(),
        ball.indices.len(),
        "a normal at every corner"
    );
    let vector = |v: &[f64], i: u32| {
        let i = 3 * i as usize;
        Vec3::new(v[i], v[i + 1], v[i + 2])
    };
    for (&i, &k) in ball.indices.iter().zip(&ball.normal_indices) {
        let (x, n) = (vector(&ball.positions, i), vector(&ball.normals, k));
        assert!((n.length() - 1.0).abs() < 1e-12, "unit normals");
        // On an icosphere the smooth normal is the radial direction to
        // within the facets' tilt: the angle between them stays below 3°
        // (the mean of the five or six faces around a vertex is nearly
        // symmetric about the radius).
        let angle = n.angle_between(x.normalize()).to_degrees();
        assert!(angle < 3.0, "vertex {i}: {angle}° from radial");
    }
    let rope = models.iter().find(|m| m.name == "rope").expect("rope");
    assert!(text.contains("\no rope\ns off\nl "), "the rope as lines");
    assert!(rope.mesh.indices.is_empty() || rope.mesh.face_arities.iter().all(|&a| a == 2));
}

#[test]
fn obj_lines_come_in_the_scenes_spring_order() {
    // A body of lines lists its springs as `l` lines in the scene's order
    // (the world stores them in its own: these came out [0,1], [3,0],
    // [1,2], [2,3]).
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world
        .add_body("x", common::springs_out_of_order(0.0))
        .expect("valid body");
    let dir = tempfile::tempdir().expect("tempdir");
    let path = write_frame(dir.path(), 0, &world, FrameFormat::Obj).expect("frame");
    let text = std::fs::read_to_string(&path).expect("read");
    let lines: Vec<&str> = text.lines().filter(|l| l.starts_with("l ")).collect();
    assert_eq!(lines, ["l 3 4", "l 2 3", "l 1 2", "l 4 1"]);
}
