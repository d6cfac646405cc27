//! The user's hand: grab the particle nearest the cursor and drag it with a
//! damped spring ([`MouseSpring`] in `World::forces`, removed on release,
//! so a fast release throws), or push bodies about with a sphere collider
//! that follows the cursor (a kinematic [`Collider`] whose path is the
//! cursor's motion over each frame).

use macroquad::math::{Rect, Vec2, Vec3};
use sprung::colliders::Path;
use sprung::forces::MouseSpring;
use sprung::{Collider, ContactResponse, Real, Shape, World};

use crate::camera::{to_f32, to_f64, View};

/// A particle further than this from the cursor (pixels) is not grabbed.
pub const REACH: f32 = 24.0;

/// Angular frequency of a grabbed body on the hand's spring (rad/s).
const HAND_OMEGA: Real = 15.0;

/// A grabbed particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grab {
    /// Its index.
    pub particle: usize,
    /// The cursor's point in the world (m), on the plane through where the
    /// particle was grabbed, facing the camera.
    pub target: Vec3,
    anchor: Vec3,
}

/// Seconds the poking sphere takes to grow to full size, so that it
/// pushes what it appears on out gently instead of all at once.
const POKE_GROWTH: Real = 0.3;

/// The grab and the poking sphere.
#[derive(Debug, Default)]
pub struct Hand {
    /// The particle being dragged.
    pub grab: Option<Grab>,
    /// Index of the poking sphere in `World::colliders`.
    pub poke: Option<usize>,
    /// Full radius of the poking sphere (m) and how grown it is (0 to 1).
    poke_size: (Real, Real),
}

/// The free particle nearest the cursor on the screen, within [`REACH`];
/// among those very near it (a third of the reach), the one in front.
pub fn pick(world: &World, view: &View, viewport: Rect, cursor: Vec2) -> Option<usize> {
    let mut best: Option<(usize, (u8, f32))> = None;
    for (i, &p) in world.particles.position.iter().enumerate() {
        if world.particles.is_pinned(i) {
            continue;
        }
        let Some((screen, depth)) = view.project(to_f32(p), viewport) else {
            continue;
        };
        let distance = screen.distance(cursor);
        if distance > REACH {
            continue;
        }
        let key = if distance < REACH / 3.0 {
            (0, depth)
        } else {
            (1, distance)
        };
        if best.is_none_or(|(_, k)| key < k) {
            best = Some((i, key));
        }
    }
    best.map(|(i, _)| i)
}

impl Hand {
    /// Grab `particle` with the cursor at `cursor` (a [`MouseSpring`]).
    pub fn grab(&mut self, world: &mut World, particle: usize, dt: Real) {
        let anchor = to_f32(world.particles.position[particle]);
        self.grab = Some(Grab {
            particle,
            target: anchor,
            anchor,
        });
        world.forces.set(spring(world, particle, anchor, dt));
    }

    /// Let go: remove the spring (the particle keeps its velocity).
    pub fn release(&mut self, world: &mut World) {
        self.grab = None;
        world.forces.remove::<MouseSpring>();
    }

    /// Move the grabbed particle's target under the cursor.
    pub fn drag(&mut self, world: &mut World, view: &View, viewport: Rect, cursor: Vec2, dt: Real) {
        if let Some(grab) = self.grab.as_mut() {
            grab.target = view.cursor_point(cursor, grab.anchor, viewport);
            world
                .forces
                .set(spring(world, grab.particle, grab.target, dt));
        }
    }

    /// Turn the poking sphere (radius `radius`, m) on at `centre`, or off.
    pub fn toggle_poke(&mut self, world: &mut World, centre: Vec3, radius: f32) {
        match self.poke.take() {
            Some(index) if index < world.colliders.len() => {
                world.colliders.remove(index);
            }
            Some(_) => {}
            None => {
                self.poke = add_poke(world, centre);
                self.poke_size = (radius as Real, 0.0);
            }
        }
    }

    /// Move the poking sphere towards `centre` over the next `span` seconds
    /// of simulated time (a straight path, so that it sweeps through bodies
    /// and carries them along instead of jumping), at most 10 of its radii
    /// per second of it, and grow it over `wall` seconds of the frame.
    pub fn move_poke(&mut self, world: &mut World, centre: Vec3, span: Real, wall: Real) {
        let now = world.time();
        let Some(collider) = self.poke.and_then(|i| world.colliders.get_mut(i)) else {
            return;
        };
        let (radius, grown) = self.poke_size;
        let grown = (grown + wall / POKE_GROWTH).min(1.0);
        self.poke_size.1 = grown;
        if let Ok(shape) = Shape::sphere(sprung::Vec3::ZERO, radius * grown.max(0.02)) {
            collider.shape = shape;
        }
        let start = collider
            .path
            .as_ref()
            .map_or(to_f64(centre), |p| p.offset_at(now));
        let step = to_f64(centre) - start;
        let reach = 10.0 * radius * span;
        let end = start + step * (reach / step.length().max(reach)).min(1.0);
        let keyframes = if span > 0.0 {
            vec![(now, start), (now + span, end)]
        } else {
            vec![(now, end)]
        };
        if let Ok(path) = Path::new(keyframes) {
            collider.path = Some(path);
        }
    }
}

/// A sphere collider at `centre`, tiny until [`Hand::move_poke`] grows it,
/// pushed onto the world.
fn add_poke(world: &mut World, centre: Vec3) -> Option<usize> {
    let shape = Shape::sphere(sprung::Vec3::ZERO, 1e-3).ok()?;
    let response = ContactResponse::Projection {
        restitution: 0.2,
        friction: 0.4,
    };
    let path = Path::new(vec![(world.time(), to_f64(centre))]).ok()?;
    let collider = Collider::new(shape, response).ok()?.with_path(path);
    world.colliders.push(collider);
    Some(world.colliders.len() - 1)
}

/// The hand's spring on `particle`: stiff enough to carry its whole body
/// (`k = M ω²`), damped at about 0.4 of critical, both capped so that an
/// explicit step of `dt` on the particle alone stays stable.
fn spring(world: &World, particle: usize, target: Vec3, dt: Real) -> MouseSpring {
    let m = world.particles.mass[particle];
    let body_mass: Real = world
        .bodies
        .iter()
        .find(|b| b.particles.contains(&particle))
        .map_or(m, |b| {
            world.particles.mass[b.particles.clone()].iter().sum()
        });
    let stiffness = (body_mass * HAND_OMEGA * HAND_OMEGA).min(0.1 * m / (dt * dt));
    let damping = (0.8 * (stiffness * body_mass).sqrt()).min(0.4 * m / dt);
    MouseSpring {
        particle,
        target: to_f64(target),
        stiffness,
        damping,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Bounds;
    use crate::demos::{find, Source};
    use macroquad::math::vec2;

    const VIEWPORT: Rect = Rect {
        x: 300.0,
        y: 0.0,
        w: 900.0,
        h: 700.0,
    };

    fn world(name: &str) -> World {
        match Source::Demo(find(name).unwrap_or(0)).load() {
            Ok(scene) => scene.world,
            Err(e) => panic!("{e}"),
        }
    }

    fn view(world: &World, flat: bool) -> View {
        let bounds = Bounds::of(world.particles.position.iter().map(|&p| to_f32(p)));
        View::framing(flat, bounds, VIEWPORT)
    }

    #[test]
    fn a_dragged_particle_follows_the_cursor() {
        let mut world = world("ball2d");
        let view = view(&world, true);
        let particle = 4;
        let at = view.project(to_f32(world.particles.position[particle]), VIEWPORT);
        let cursor = at.map_or(Vec2::ZERO, |(s, _)| s);
        assert_eq!(pick(&world, &view, VIEWPORT, cursor), Some(particle));
        let mut hand = Hand::default();
        let dt = 5e-4;
        hand.grab(&mut world, particle, dt);
        let moved = cursor + vec2(120.0, -80.0);
        hand.drag(&mut world, &view, VIEWPORT, moved, dt);
        for _ in 0..4000 {
            assert!(world.step(dt).is_ok());
        }
        let target = hand.grab.map(|g| g.target).unwrap_or_default();
        let distance = (to_f32(world.particles.position[particle]) - target).length();
        assert!(distance < 0.1, "{distance} m from the cursor");
        hand.release(&mut world);
        assert!(world.forces.get::<MouseSpring>().is_none());
    }

    /// The `bullet` demo with its ball at rest above the cloth, one of
    /// the ball's particles dragged towards a point 2 m below the cloth
    /// for 0.1 s, as fast as the hand drags, then let go; the crossings
    /// between bodies over its steps of 2.5e-4 s, and the fastest the
    /// ball's centre moved (m/s).
    fn thrown_at_the_cloth(ccd: bool) -> (usize, Real) {
        let mut world = world("bullet");
        world.contacts.settings.ccd = ccd;
        world
            .particles
            .velocity
            .iter_mut()
            .for_each(|v| *v = sprung::Vec3::ZERO);
        let ball = world
            .body("ball")
            .map(|b| b.particles.clone())
            .unwrap_or_default();
        let particle = ball.start;
        let dt = 2.5e-4;
        let mut hand = Hand::default();
        hand.grab(&mut world, particle, dt);
        let target = Vec3::new(0.0, -2.0, 0.0);
        world.forces.set(spring(&world, particle, target, dt));
        let mut before = sprung_io::crossings::Surfaces::of_world(&world);
        let (mut between, mut fastest) = (0, 0.0);
        for step in 0..1200 {
            if step == 400 {
                hand.release(&mut world);
            }
            assert!(world.step(dt).is_ok(), "step {step}");
            let now = sprung_io::crossings::Surfaces::of_world(&world);
            between += sprung_io::crossings::count(Some(&before), &now).between();
            before = now;
            let speed = world.particles.velocity[ball.clone()]
                .iter()
                .sum::<sprung::Vec3>()
                .length()
                / ball.len() as Real;
            fastest = Real::max(fastest, speed);
        }
        (between, fastest)
    }

    #[test]
    fn a_ball_thrown_by_hand_at_a_cloth_does_not_pass_through_it() {
        // Claim: the hand's spring yanks the ball into the cloth faster
        // than the penalty alone stops (10 m/s at the default stiffness):
        // without the CCD it goes through (crossings counted), with
        // it no crossing between the bodies in any step, exactly.
        let (between, fastest) = thrown_at_the_cloth(true);
        assert_eq!(between, 0, "crossings, the ball at up to {fastest} m/s");
        assert!(fastest > 10.0, "thrown at {fastest} m/s");
        let (without, _) = thrown_at_the_cloth(false);
        assert!(without > 0, "no crossing without the CCD");
    }

    #[test]
    fn pinned_particles_and_empty_space_are_not_picked() {
        let world = world("rope");
        let view = view(&world, true);
        let pinned = view
            .project(Vec3::ZERO, VIEWPORT)
            .map_or(Vec2::ZERO, |s| s.0);
        assert_ne!(pick(&world, &view, VIEWPORT, pinned), Some(0));
        assert_eq!(pick(&world, &view, VIEWPORT, vec2(-500.0, -500.0)), None);
    }

    #[test]
    fn the_poking_sphere_pushes_particles_out() {
        let mut world = world("ball3d");
        world.set_gravity(sprung::Vec3::ZERO);
        let mut hand = Hand::default();
        let centre = to_f32(world.centroid(0).unwrap_or_default());
        hand.toggle_poke(&mut world, centre + Vec3::new(2.0, 0.0, 0.0), 0.3);
        assert!(hand.poke.is_some());
        // Without the collider, the ball's surface near x = +0.5 m would be inside.
        let poke = centre + Vec3::new(0.4, 0.0, 0.0);
        // 3 m/s at most (10 radii per second): 1.2 s to get there and stay.
        for _ in 0..60 {
            hand.move_poke(&mut world, poke, 0.02, 0.02);
            for _ in 0..100 {
                assert!(world.step(2e-4).is_ok());
            }
        }
        let inside = world
            .particles
            .position
            .iter()
            .filter(|&&p| (to_f32(p) - poke).length() < 0.29)
            .count();
        assert_eq!(inside, 0);
        // Pushed, not blown apart: the 1 kg ball is knocked ahead of the
        // sphere (3 m/s at most, so a few J) and rings; a blow-up or a
        // sphere that jumped into it would give far more.
        let kinetic = world.energies().kinetic;
        assert!(kinetic < 40.0, "{kinetic} J");
        hand.toggle_poke(&mut world, centre, 0.3);
        assert_eq!(world.colliders.len(), 1);
    }
}
