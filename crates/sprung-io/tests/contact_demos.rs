//! The contact demos, loaded from `scenes/` and run: the stack stays
//! stacked with no ball inside another, and the folding cloth never passes
//! through itself. And closed surfaces colliding with themselves: a hollow
//! ball and a ring collapsing on a floor.

use std::path::Path;

use sprung::contact::grid::Grid;
use sprung::contact::inside::deepest_interpenetration;
use sprung::{Real, Vec3, World};
use sprung_io::{load_scene, parse_scene, Scene};

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

/// A scene of one body with `self_collision`, no gas, on a floor (a plane
/// collider with friction 0.5), contact thickness 1 cm, friction 0.3, at
/// dt = 1e-4 s; `body` is the rest of its `[[body]]` table.
fn collapsing(body: &str) -> Scene {
    let text = format!(
        "[sim]\ndt = 1e-4\nsteps = 1\n[contact]\nthickness = 0.01\nfriction = 0.3\n[[collider]]\nplane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}\nfriction = 0.5\n[[body]]\nname = \"b\"\nself_collision = true\n{body}"
    );
    parse_scene(&text, Path::new("collapsing.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// Run `scene` for `seconds`, calling `check` every hundredth of a second;
/// return the most the total energy rose above its start (J).
fn collapse(scene: &mut Scene, seconds: Real, mut check: impl FnMut(&World)) -> Real {
    let start = scene.world.energies().total();
    let mut rise: Real = 0.0;
    let per_check = (0.01 / scene.dt).round() as usize;
    while scene.world.time() < seconds {
        for _ in 0..per_check {
            scene.world.step(scene.dt).unwrap_or_else(|e| panic!("{e}"));
        }
        rise = rise.max(scene.world.energies().total() - start);
        check(&scene.world);
    }
    rise
}

#[test]
fn a_hollow_ball_collapsing_onto_itself_neither_crosses_itself_nor_gains_energy() {
    // An icosphere of 642 particles (radius 0.3 m, 1 kg, 30 N/m, no gas)
    // resting on the floor slumps and folds in on itself under gravity,
    // from 0.6 m to some 0.16 m high, its particles meeting their own
    // surface from inside (up to 180 touches at once). Its own closed
    // surface must push them back to the side they came from (outward, as
    // against another body, would push them through), and its edges meet
    // each other as a cloth's do. Its bending springs hold the creases,
    // where particles near each other in the mesh do not collide
    // (`contact/links.rs`). Claims: at every hundredth of a second over
    // 1 s no edge passes through one of its own triangles; and nothing
    // drives it (gravity, damped springs, friction, an inelastic floor),
    // so the total energy never rises above its start by more than 1 mJ
    // (symplectic Euler's wobble at this step is far below). Before, it
    // crossed itself from 0.37 s on.
    let mut scene = collapsing(
        "sphere = { radius = 0.3, subdivisions = 3 }\ntotal_mass = 1.0\nstiffness = 30.0\ndamping = 0.05\ntranslate = [0.0, 0.32, 0.0]\n",
    );
    let mut grid = Grid::default();
    let rise = collapse(&mut scene, 1.0, |world| {
        let crossings = self_crossings(world, 0, &mut grid);
        assert_eq!(crossings, 0, "t = {:.2} s: crossed itself", world.time());
    });
    assert!(rise <= 1e-3, "the energy rose {rise} J above its start");
}

/// Whether the segments `p → q` and `r → s` (in the xy-plane) cross, not
/// at their ends.
fn segments_cross(p: Vec3, q: Vec3, r: Vec3, s: Vec3) -> bool {
    let side = |a: Vec3, b: Vec3, c: Vec3| (b - a).truncate().perp_dot((c - a).truncate());
    side(p, q, r) * side(p, q, s) < 0.0 && side(r, s, p) * side(r, s, q) < 0.0
}

#[test]
fn a_ring_folding_onto_itself_neither_crosses_itself_nor_gains_energy() {
    // A 2D ring of 60 particles (radius 0.3 m, 10 g each, 2000 N/m, no
    // gas) thrown down at 3 m/s onto the floor from 0.5 m: it flattens and
    // folds, its particles meeting their own segments from inside.
    // Claims: at every hundredth of a second over 1.5 s no two of its
    // segments that share no particle cross; and the total energy (5.64 J
    // at the start) never rises above its start by more than 1 mJ. Before,
    // its segments crossed hundreds of times and it ended with 43 J, 35 J
    // of it in contacts pushing the wrong way.
    let mut scene = collapsing(
        "ring = { particles = 60, radius = 0.3 }\nmass = 0.01\nstiffness = 2000.0\ndamping = 0.05\ntranslate = [0.0, 0.5, 0.0]\nvelocity = [0.0, -3.0, 0.0]\n",
    );
    let rise = collapse(&mut scene, 1.5, |world| {
        let x = &world.particles.position;
        let segments = &world.bodies[0].segments;
        for (k, a) in segments.iter().enumerate() {
            for b in &segments[k + 1..] {
                if a.iter().any(|i| b.contains(i)) {
                    continue;
                }
                let [p, q, r, s] = [a[0], a[1], b[0], b[1]].map(|i| x[i as usize]);
                assert!(
                    !segments_cross(p, q, r, s),
                    "t = {:.2} s: segments {a:?} and {b:?} cross",
                    world.time()
                );
            }
        }
    });
    assert!(rise <= 1e-3, "the energy rose {rise} J above its start");
}
