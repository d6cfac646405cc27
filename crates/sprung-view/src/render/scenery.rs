//! What surrounds the bodies: plane colliders as a faint floor (a gridded
//! square under the bodies in 3D; the solid side shaded, edged and hatched
//! in 2D) and sphere colliders as grey balls.

use sprung::{Real, Shape, Vec3};

use super::camera::{Bounds, Camera, Projection};
use super::canvas::Canvas;
use super::clip;
use super::style::{shade, FLOOR, FLOOR_LINE, OBSTACLE, OBSTACLE_LIGHT};

/// Draw every plane of `colliders` (before anything else: floors lie
/// behind the bodies).
pub fn floors(canvas: &mut Canvas, camera: &Camera, bounds: &Bounds, colliders: &[Shape]) {
    for shape in colliders {
        if let Shape::Plane { point, normal } = *shape {
            if camera.is_orthographic() {
                floor_2d(canvas, camera, point, normal);
            } else {
                floor_3d(canvas, camera, bounds, point, normal);
            }
        }
    }
}

/// Draw a sphere collider of `radius` (m) about `centre` (m) as a disc.
pub fn sphere(canvas: &mut Canvas, camera: &Camera, centre: Vec3, radius: Real) {
    let v = camera.view(centre);
    let radius = if camera.is_orthographic() {
        // The sphere's cut by the plane z = 0.
        (radius * radius - centre.z * centre.z).max(0.0).sqrt()
    } else {
        radius
    };
    if v.depth <= camera.near() || radius <= 0.0 {
        return;
    }
    let pixels = (radius * camera.pixels_per_metre(v.depth)) as f32;
    canvas.ball(
        camera.to_pixels(v),
        pixels,
        OBSTACLE_LIGHT,
        shade(OBSTACLE, 0.8),
        shade(OBSTACLE, 0.6),
    );
}

/// The solid side of the line where the plane cuts z = 0, shaded, with
/// its edge drawn and hatched like a ground in a mechanics drawing.
fn floor_2d(canvas: &mut Canvas, camera: &Camera, point: Vec3, normal: Vec3) {
    let in_plane = Vec3::new(normal.x, normal.y, 0.0);
    let Some(n) = in_plane.try_normalize() else {
        return;
    };
    // The point s n of z = 0 on the plane: (s n - point) · normal = 0.
    let on_line = n * (point.dot(normal) / n.dot(normal));
    let along = Vec3::new(-n.y, n.x, 0.0);
    let metres = |pixels: u32| Real::from(pixels) / camera.pixels_per_metre(0.0);
    let reach = 4.0 * (metres(camera.width) + metres(camera.height))
        + camera.view(on_line).x.abs()
        + camera.view(on_line).y.abs();
    let px = |p: Vec3| camera.to_pixels(camera.view(p));
    let (a, b) = (on_line - reach * along, on_line + reach * along);
    let solid = [px(a), px(b), px(b - reach * n), px(a - reach * n)];
    canvas.polygon(&solid, FLOOR, false);
    let edge = shade(FLOOR_LINE, 0.8);
    // Hatches every 14 px along the visible part of the edge.
    let step = metres(14);
    let hatch = metres(9);
    // The point of the edge nearest the picture's centre.
    let offset = camera.view(on_line);
    let centre = on_line - along * (offset.x * along.x + offset.y * along.y);
    let count = ((metres(camera.width) + metres(camera.height)) / step).ceil() as i64;
    for k in -count..=count {
        let start = centre + along * (k as Real * step);
        let end = start - hatch * (n + along) / 2f64.sqrt();
        canvas.line(px(start), px(end), FLOOR_LINE, 1.0);
    }
    canvas.line(px(a), px(b), edge, 1.5);
}

/// A square of the plane under the bodies, with a grid at a round spacing.
fn floor_3d(canvas: &mut Canvas, camera: &Camera, bounds: &Bounds, point: Vec3, normal: Vec3) {
    if let Projection::Perspective { eye, .. } = camera.projection {
        if (eye - point).dot(normal) <= 0.0 {
            return; // seen from below: the floor would hide the bodies
        }
    }
    let centre = bounds.centre();
    let centre = centre - (centre - point).dot(normal) * normal;
    let u = normal.any_orthonormal_vector();
    let w = normal.cross(u);
    let half = 0.75 * bounds.diagonal().max(0.5);
    let spacing = round_spacing(half / 4.0);
    let half = (half / spacing).ceil() * spacing;
    let near = camera.near();
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .map(|(a, b)| camera.view(centre + half * (a * u + b * w)));
    let visible = clip::polygon(&corners, near);
    let pixels: Vec<(f32, f32)> = visible.iter().map(|&v| camera.to_pixels(v)).collect();
    canvas.polygon(&pixels, FLOOR, false);
    let lines = (half / spacing).round() as i64;
    for k in -lines..=lines {
        let t = k as Real * spacing;
        for (dir, across) in [(u, w), (w, u)] {
            let a = camera.view(centre + t * across - half * dir);
            let b = camera.view(centre + t * across + half * dir);
            if let Some((a, b)) = clip::segment(a, b, near) {
                canvas.line(camera.to_pixels(a), camera.to_pixels(b), FLOOR_LINE, 1.0);
            }
        }
    }
}

/// 1, 2 or 5 times a power of ten, the nearest below `x` (m).
fn round_spacing(x: Real) -> Real {
    let x = x.max(1e-9);
    let power = 10f64.powf(x.log10().floor());
    let m = x / power;
    power
        * if m >= 5.0 {
            5.0
        } else if m >= 2.0 {
            2.0
        } else {
            1.0
        }
}
