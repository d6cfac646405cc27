//! Drawing a 3D world with the orbit camera: floors with a grid, faces
//! shaded (see [`crate::shading`]), springs coloured by strain, particles
//! of bodies without faces and pinned particles as small spheres, sphere
//! colliders (the poking one see-through).

use std::ops::Range;

use macroquad::math::{vec2, Vec3};
use macroquad::models::{draw_line_3d, draw_mesh, Mesh, Vertex};
use macroquad::prelude::{set_camera, set_default_camera, Camera3D};
use sprung::{Shape, World};

use crate::camera::{to_f32, Bounds};
use crate::palette;
use crate::render::Look;
use crate::shading::{Batch, Light};

/// Particles drawn as spheres in a body without faces, at most.
const MAX_DOTS: usize = 2000;

/// Scratch buffers kept between frames.
#[derive(Default)]
pub struct Renderer3d {
    batch: Batch,
    x: Vec<Vec3>,
}

impl Renderer3d {
    /// Draw `world` through `camera`; `bounds` sizes the floors.
    pub fn draw(&mut self, world: &World, camera: &Camera3D, bounds: Bounds, look: &Look) {
        set_camera(camera);
        let light = Light::behind(camera.position, camera.target);
        let mut x = std::mem::take(&mut self.x);
        x.clear();
        x.extend(world.particles.position.iter().map(|&p| to_f32(p)));
        let mut poke = None;
        for (index, collider) in world.colliders.iter().enumerate() {
            match collider.shape_at(world.time()) {
                Shape::Plane { point, normal } => floor(to_f32(point), to_f32(normal), bounds),
                Shape::Sphere { centre, radius } if Some(index) == look.poke => {
                    poke = Some((to_f32(centre), radius as f32, palette::HAND));
                }
                Shape::Sphere { centre, radius } => {
                    let sphere = (to_f32(centre), radius as f32, palette::GROUND_EDGE);
                    self.batch.spheres([sphere], 1.0, &light);
                }
            }
        }
        for (index, body) in world.bodies.iter().enumerate() {
            let has_faces = !body.faces.is_empty();
            if has_faces && look.faces {
                self.batch
                    .faces(&x, &body.faces, palette::body(index), &light);
            }
            if !has_faces || look.springs {
                let lift = if has_faces { 0.004 } else { 0.0 };
                springs(
                    world,
                    &x,
                    body.springs.clone(),
                    (light.eye, lift),
                    look.full_strain,
                );
            }
            let radius = 0.12 * mean_rest_length(world, body.springs.clone());
            let dots = !has_faces && body.particles.len() <= MAX_DOTS;
            let particles = &world.particles;
            let spheres = body.particles.clone().filter_map(|i| {
                if particles.is_pinned(i) {
                    Some((x[i], radius, palette::PINNED))
                } else {
                    dots.then(|| (x[i], radius, palette::body(index)))
                }
            });
            self.batch.spheres(spheres, 1.0, &light);
        }
        for m in &world.muscles.list {
            let [a, b] = world.springs.endpoints(m.spring).map(|i| x[i as usize]);
            draw_line_3d(a, b, palette::muscle(m.phase()));
        }
        let rods = &world.rods;
        for r in 0..rods.len() {
            let (a, b) = (x[rods.first[r] as usize], x[rods.second[r] as usize]);
            draw_line_3d(a, b, palette::ROD);
        }
        // Joins: rods above, springs here, in the rods' colour.
        for j in (0..world.joins.len()).filter(|&j| !world.join_broken(j)) {
            if let sprung::tearing::JoinLink::Spring(_) = world.joins[j].link {
                let [a, b] = world.joins[j].particles.map(|i| x[i as usize]);
                draw_line_3d(a, b, palette::ROD);
            }
        }
        if let Some(sphere) = poke {
            self.batch.spheres([sphere], 0.55, &light);
        }
        self.x = x;
        set_default_camera();
    }
}

/// Every spring of `range` as a line coloured by its strain, moved `lift`
/// of the way towards the eye so that lines on a surface stay visible.
fn springs(world: &World, x: &[Vec3], range: Range<usize>, (eye, lift): (Vec3, f32), full: f32) {
    let s = &world.springs;
    for k in range.filter(|&k| !s.is_broken(k)) {
        let (a, b) = (x[s.first()[k] as usize], x[s.second()[k] as usize]);
        let rest = s.rest_length[k] as f32;
        let strain = ((b - a).length() - rest) / rest;
        let colour = palette::strain(strain, full);
        draw_line_3d(a + (eye - a) * lift, b + (eye - b) * lift, colour);
    }
}

/// Mean rest length of the springs in `range` (m), 0.05 m if none.
fn mean_rest_length(world: &World, range: Range<usize>) -> f32 {
    let count = range.len();
    if count == 0 {
        return 0.05;
    }
    (world.springs.rest_length[range].iter().sum::<f64>() / count as f64) as f32
}

/// A floor: a square of ground around the scene with a grid on it.
fn floor(point: Vec3, normal: Vec3, bounds: Bounds) {
    let normal = normal.normalize_or_zero();
    let centre = bounds.centre();
    let centre = centre - normal * (centre - point).dot(normal);
    let helper = if normal.y.abs() < 0.9 {
        Vec3::Y
    } else {
        Vec3::X
    };
    let u = normal.cross(helper).normalize_or_zero();
    let v = normal.cross(u);
    let spacing = grid_spacing(bounds.radius());
    let lines = 14;
    let half = spacing * lines as f32;
    let corner = |s: f32, t: f32| centre + u * s * half + v * t * half;
    let quad = [
        corner(-1., -1.),
        corner(1., -1.),
        corner(1., 1.),
        corner(-1., 1.),
    ];
    let vertices = quad
        .iter()
        .map(|&p| Vertex::new2(p - normal * 0.002 * half, vec2(0.0, 0.0), palette::GROUND))
        .collect();
    draw_mesh(&Mesh {
        vertices,
        indices: vec![0, 1, 2, 0, 2, 3],
        texture: None,
    });
    for i in -lines..=lines {
        let s = i as f32 / lines as f32;
        draw_line_3d(corner(s, -1.0), corner(s, 1.0), palette::GRID);
        draw_line_3d(corner(-1.0, s), corner(1.0, s), palette::GRID);
    }
}

/// A round grid spacing (m) for a scene of size `radius`: 1, 2 or 5 × 10^n.
pub fn grid_spacing(radius: f32) -> f32 {
    let raw = radius / 5.0;
    let decade = 10f32.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= raw)
        .unwrap_or(decade)
}

#[cfg(test)]
mod tests {
    use super::grid_spacing;

    #[test]
    fn grid_spacing_is_round() {
        for (radius, spacing) in [(1.0, 0.2), (3.0, 1.0), (10.0, 2.0), (0.3, 0.1)] {
            let got = grid_spacing(radius);
            assert!((got - spacing).abs() < 1e-5 * spacing, "{radius}: {got}");
        }
    }
}
