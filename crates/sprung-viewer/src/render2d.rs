//! Drawing a 2D world (the xy-plane) in screen space: floors as ground
//! below a line, closed loops filled, springs coloured by strain, particles
//! as dots (pinned ones gold).

use macroquad::color::Color;
use macroquad::math::{vec2, Rect, Vec2};
use macroquad::shapes::{draw_circle, draw_circle_lines, draw_line, draw_rectangle, draw_triangle};
use sprung::{Shape, World};

use crate::camera::{to_f32, View};
use crate::palette;
use crate::render::Look;
use crate::render3d::grid_spacing;

/// Draw `world` seen through the 2D `view` in `viewport`.
pub fn draw(world: &World, view: &View, viewport: Rect, look: &Look) {
    let screen = |p: sprung::Vec3| {
        view.project(to_f32(p), viewport)
            .map_or(Vec2::ZERO, |(s, _)| s)
    };
    grid(view, viewport);
    for (index, collider) in world.colliders.iter().enumerate() {
        match collider.shape_at(world.time()) {
            Shape::Plane { point, normal } => ground(screen(point), to_f32(normal).truncate()),
            Shape::Sphere { centre, radius } => {
                let c = screen(centre);
                let r = radius as f32 * view.pixels_per_metre(0.0, viewport);
                if Some(index) == look.poke {
                    draw_circle(c.x, c.y, r, Color::new(0.37, 0.88, 1.0, 0.25));
                    draw_circle_lines(c.x, c.y, r, 2.0, palette::HAND);
                } else {
                    draw_circle(c.x, c.y, r, palette::GROUND);
                    draw_circle_lines(c.x, c.y, r, 2.0, palette::GROUND_EDGE);
                }
            }
        }
    }
    let x: Vec<Vec2> = world
        .particles
        .position
        .iter()
        .map(|&p| screen(p))
        .collect();
    for (index, body) in world.bodies.iter().enumerate() {
        if look.faces && !body.segments.is_empty() {
            fill_loop(
                &x,
                &body.segments,
                palette::shade(palette::body(index), 0.8, 0.35),
            );
        }
        if look.faces {
            let colour = palette::shade(palette::body(index), 0.8, 0.30);
            for &[a, b, c] in &body.faces {
                draw_triangle(x[a as usize], x[b as usize], x[c as usize], colour);
            }
        }
    }
    let s = &world.springs;
    for k in (0..s.len()).filter(|&k| !s.is_broken(k)) {
        let (a, b) = (s.first()[k] as usize, s.second()[k] as usize);
        let length = (world.particles.position[b] - world.particles.position[a]).length();
        let strain = ((length - s.rest_length[k]) / s.rest_length[k]) as f32;
        let (p, q) = (x[a], x[b]);
        draw_line(
            p.x,
            p.y,
            q.x,
            q.y,
            2.0,
            palette::strain(strain, look.full_strain),
        );
    }
    for m in &world.muscles.list {
        let [a, b] = s.endpoints(m.spring).map(|i| x[i as usize]);
        draw_line(a.x, a.y, b.x, b.y, 3.0, palette::muscle(m.phase()));
    }
    let rods = &world.rods;
    for r in 0..rods.len() {
        let (a, b) = (x[rods.first[r] as usize], x[rods.second[r] as usize]);
        draw_line(a.x, a.y, b.x, b.y, 4.0, palette::ROD);
    }
    let radius = particle_radius(world.particles.len());
    for (index, body) in world.bodies.iter().enumerate() {
        for i in body.particles.clone() {
            let colour = if world.particles.is_pinned(i) {
                palette::PINNED
            } else {
                palette::body(index)
            };
            draw_circle(x[i].x, x[i].y, radius, colour);
        }
    }
}

/// Dot radius (pixels): smaller when there are many.
pub fn particle_radius(count: usize) -> f32 {
    if count > 400 {
        2.5
    } else {
        4.5
    }
}

/// Faint lines every round number of metres.
fn grid(view: &View, viewport: Rect) {
    let View::Flat(flat) = view else {
        return;
    };
    let half = vec2(viewport.w, viewport.h) / (2.0 * flat.scale);
    let spacing = grid_spacing(half.length());
    let colour = Color::new(1.0, 1.0, 1.0, 0.035);
    let first = ((flat.centre - half) / spacing).floor();
    let last = ((flat.centre + half) / spacing).ceil();
    let to_screen = |p: Vec2| {
        view.project(p.extend(0.0), viewport)
            .map_or(Vec2::ZERO, |s| s.0)
    };
    for i in first.x as i64..=last.x as i64 {
        let s = to_screen(vec2(i as f32 * spacing, 0.0));
        draw_line(s.x, viewport.y, s.x, viewport.bottom(), 1.0, colour);
    }
    for j in first.y as i64..=last.y as i64 {
        let s = to_screen(vec2(0.0, j as f32 * spacing));
        draw_line(viewport.x, s.y, viewport.right(), s.y, 1.0, colour);
    }
}

/// The solid side of a plane through screen point `at` with world normal
/// `normal` (y up; the screen's y runs down).
fn ground(at: Vec2, normal: Vec2) {
    let n = vec2(normal.x, -normal.y).normalize_or_zero();
    let along = vec2(-n.y, n.x) * 1e4;
    let (a, b) = (at - along, at + along);
    let depth = -n * 1e4;
    draw_triangle(a, b, b + depth, palette::GROUND);
    draw_triangle(a, b + depth, a + depth, palette::GROUND);
    draw_line(a.x, a.y, b.x, b.y, 2.0, palette::GROUND_EDGE);
}

/// Fill a closed loop of segments as a fan about its centroid.
fn fill_loop(x: &[Vec2], segments: &[[u32; 2]], colour: Color) {
    if segments.is_empty() {
        return;
    }
    let centre = segments.iter().map(|s| x[s[0] as usize]).sum::<Vec2>() / segments.len() as f32;
    for &[a, b] in segments {
        draw_triangle(centre, x[a as usize], x[b as usize], colour);
    }
}

/// A dim veil over the viewport, behind messages.
pub fn veil(viewport: Rect) {
    draw_rectangle(
        viewport.x,
        viewport.y,
        viewport.w,
        viewport.h,
        Color::new(0.0, 0.0, 0.0, 0.45),
    );
}
