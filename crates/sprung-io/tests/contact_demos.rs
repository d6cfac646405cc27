//! The contact demos, loaded from `scenes/` and run: the stack stays
//! stacked with no ball inside another, and the folding cloth never passes
//! through itself.

use std::path::Path;

use sprung::contact::grid::Grid;
use sprung::contact::inside::deepest_interpenetration;
use sprung::{Real, Vec3, World};
use sprung_io::{load_scene, Scene};

fn demo(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_stack_settles_and_stays_stacked_for_ten_seconds() {
    // Three gas balls (radius 0.5 m) dropped into a tube 1.1 m wide. After
    // 2 s they rest; from then to 10 s, at every tenth of a second, each
    // ball's centroid is above the one below by most of a diameter (0.8 m:
    // they squash a little), and no particle of one is inside another
    // deeper than the contact thickness.
    let mut scene = demo("stack.toml");
    let thickness = scene.world.contacts.settings.thickness;
    let per_record = (0.1 / scene.dt).round() as usize;
    let records = (10.0 / (per_record as Real * scene.dt)).round() as usize;
    for record in 1..=records {
        for _ in 0..per_record {
            scene.world.step(scene.dt).unwrap_or_else(|e| panic!("{e}"));
        }
        let depth = deepest_interpenetration(&scene.world.bodies, &scene.world.particles.position);
        assert!(
            depth <= thickness,
            "t = {:.1} s: {depth} m inside",
            scene.world.time()
        );
        if scene.world.time() < 2.0 {
            continue;
        }
        let height = |body: usize| scene.world.centroid(body).expect("a body").y;
        for body in 1..3 {
            let gap = height(body) - height(body - 1);
            assert!(
                gap > 0.8,
                "record {record}, t = {:.1} s: ball {body} only {gap} m above the one below",
                scene.world.time()
            );
        }
    }
}

/// Whether the segment `p → q` crosses the triangle `(a, b, c)` (not at
/// its ends).
fn crosses(p: Vec3, q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
    let (e1, e2, d) = (b - a, c - a, q - p);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-18 {
        return false;
    }
    let s = p - a;
    let u = s.dot(h) / det;
    let k = s.cross(e1);
    let v = d.dot(k) / det;
    let t = e2.dot(k) / det;
    u > 0.0 && v > 0.0 && u + v < 1.0 && t > 0.0 && t < 1.0
}

/// Edges of the body's own triangles that pass through another of its
/// triangles (not one they share a particle with).
fn self_crossings(world: &World, body: usize, grid: &mut Grid) -> usize {
    let x = &world.particles.position;
    let (faces, edges) = (&world.bodies[body].faces, &world.bodies[body].edges);
    let boxes = |points: &[u32]| {
        let (mut low, mut high) = (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY));
        for &i in points {
            low = low.min(x[i as usize]);
            high = high.max(x[i as usize]);
        }
        (low, high)
    };
    grid.build(0.05, faces.iter().map(|f| boxes(f)));
    let mut count = 0;
    for edge in edges {
        let (low, high) = boxes(edge);
        let mut seen = Vec::new();
        grid.query(low, high, |t| {
            let face = faces[t as usize];
            if seen.contains(&t) || face.contains(&edge[0]) || face.contains(&edge[1]) {
                return;
            }
            seen.push(t);
            let [a, b, c] = face.map(|i| x[i as usize]);
            if crosses(x[edge[0] as usize], x[edge[1] as usize], a, b, c) {
                count += 1;
            }
        });
    }
    count
}

/// The most self-crossings of the fold demo's cloth at every twentieth of
/// a second over its 4 s, with `self_collision` and a contact `thickness`
/// (m, the scene's if none).
fn fold_crossings(self_collision: bool, thickness: Option<Real>) -> usize {
    let mut scene = demo("fold.toml");
    scene.world.bodies[0].contact.self_collision = self_collision;
    if let Some(thickness) = thickness {
        scene.world.contacts.settings.thickness = thickness;
    }
    let per_record = (0.05 / scene.dt).round() as usize;
    let mut grid = Grid::default();
    let mut worst = 0;
    while scene.world.time() < 4.0 {
        for _ in 0..per_record {
            scene.world.step(scene.dt).unwrap_or_else(|e| panic!("{e}"));
        }
        worst = worst.max(self_crossings(&scene.world, 0, &mut grid));
    }
    worst
}

#[test]
fn the_folding_cloth_never_crosses_itself() {
    // The cloth stands, slumps and folds onto itself on the floor over 4 s;
    // at every twentieth of a second no edge of it passes through one of
    // its own triangles. The check is meaningful: without self-collision
    // the same run does cross itself.
    assert_eq!(fold_crossings(true, None), 0, "the cloth crossed itself");
    assert!(
        fold_crossings(false, None) > 0,
        "without self-collision it should cross itself"
    );
}

#[test]
fn a_contact_thicker_than_the_particle_spacing_still_folds_cleanly() {
    // The fold demo's particles are 1/23 m = 43 mm apart; a 65 mm contact
    // reaches past a particle's spring-joined neighbours to others a few
    // springs away, which are left out of its self-collision (the
    // exclusion radius: a flat sheet stays at rest, a unit test of
    // `contact::links`). The folds still keep apart: the run neither blows
    // up (every step is Ok) nor crosses itself.
    assert_eq!(fold_crossings(true, Some(0.065)), 0);
}
