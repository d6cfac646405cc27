//! Drawing one snapshot: floors first, then the faint fill of closed 2D
//! bodies, then faces, springs, obstacles and normals back to front (the
//! painter's algorithm: each item at its mean depth, springs nudged half
//! their length towards the camera so they lie over the faces they edge),
//! and the pinned particles on top.
//!
//! Faces are lit by one directional light from above and behind the
//! camera: colour × (ambient + (1 - ambient) max(0, n·l)) (Lambert), with
//! the normal turned towards the viewer, so both sides of a cloth are lit
//! (the outside, counter-clockwise side in blue, the inside in sand).

use std::collections::BTreeSet;

use sprung::{Real, Shape, Vec3};

use super::camera::{Bounds, Camera, ViewPoint};
use super::canvas::Canvas;
use super::clip;
use super::image::Image;
use super::scenery;
use super::snapshot::Snapshot;
use super::strain::StrainColours;
use super::style::{
    phase_colour, shade, Style, AMBIENT, BACK, BACKGROUND, FRONT, NORMAL, OUTLINE_FILL, PARTICLE,
    PIN, ROD, SPRING_OVER_FACES_ALPHA, TRACE,
};
use super::RenderError;

/// Springs over faces shorter than this on the picture (pixels) fade.
const FADE_PIXELS: f32 = 28.0;
/// The least opacity factor of a faded spring.
const MIN_FADE: f32 = 0.35;

/// Something drawn in depth order.
#[derive(Debug, Clone, Copy)]
enum Item {
    Face(usize),
    Obstacle(usize),
    Spring(usize),
    Rod(usize),
    Normal(usize),
}

/// Draw `snapshot` as `camera` sees it, framed for `bounds` (the floor is
/// sized from them), in `style`, with `trace` (m: the path of the traced
/// particle so far, drawn as a line; empty for none).
pub fn draw(
    snapshot: &Snapshot,
    camera: &Camera,
    bounds: &Bounds,
    style: &Style,
    trace: &[Vec3],
) -> Result<Image, RenderError> {
    let mut canvas = Canvas::new(camera.width, camera.height, BACKGROUND)?;
    let model = &*snapshot.model;
    let position = &snapshot.position;
    let at = |i: u32| position.get(i as usize).copied().filter(|p| p.is_finite());
    scenery::floors(&mut canvas, camera, bounds, &snapshot.colliders);
    let near = camera.near();
    let project = |p: Vec3| {
        let v = camera.view(p);
        (v.depth >= near).then(|| camera.to_pixels(v))
    };
    for outline in &model.outlines {
        let points: Option<Vec<(f32, f32)>> =
            outline.iter().map(|&i| at(i).and_then(project)).collect();
        if let Some(points) = points {
            canvas.polygon(&points, OUTLINE_FILL, false);
        }
    }
    let faces: Vec<Option<[Vec3; 3]>> = model
        .faces
        .iter()
        .map(|f| Some([at(f[0])?, at(f[1])?, at(f[2])?]))
        .collect();
    let mut items: Vec<(Real, Item)> = Vec::new();
    for (k, face) in faces.iter().enumerate() {
        if let Some([a, b, c]) = face {
            let depth =
                (camera.view(*a).depth + camera.view(*b).depth + camera.view(*c).depth) / 3.0;
            items.push((depth, Item::Face(k)));
            if style.normals {
                items.push((depth, Item::Normal(k)));
            }
        }
    }
    for (k, shape) in snapshot.colliders.iter().enumerate() {
        if let Shape::Sphere { centre, .. } = shape {
            items.push((camera.view(*centre).depth, Item::Obstacle(k)));
        }
    }
    let bias = if camera.is_orthographic() { 0.0 } else { 0.5 };
    let surface = Surface::of(model.faces.as_slice(), position.len());
    for (k, &[i, j]) in model.springs.iter().enumerate() {
        if !(style.all_springs || surface.shows(i, j)) {
            continue;
        }
        if let (Some(a), Some(b)) = (at(i), at(j)) {
            let depth = 0.5 * (camera.view(a).depth + camera.view(b).depth);
            items.push((depth - bias * a.distance(b), Item::Spring(k)));
        }
    }
    for (k, &[i, j]) in model.rods.iter().enumerate() {
        if let (Some(a), Some(b)) = (at(i), at(j)) {
            let depth = 0.5 * (camera.view(a).depth + camera.view(b).depth);
            items.push((depth - bias * a.distance(b), Item::Rod(k)));
        }
    }
    // Far to near; the sort is stable, so equal depths (all of a 2D scene)
    // keep the order faces, obstacles, springs.
    items.sort_by(|a, b| b.0.total_cmp(&a.0));
    let light = light_direction(camera);
    let smooth = sprung::surface::vertex_normals(&model.faces, position);
    let (spring_width, spring_alpha) = if model.faces.is_empty() {
        (style.line_width, 255)
    } else {
        (0.6 * style.line_width, SPRING_OVER_FACES_ALPHA)
    };
    for &(_, item) in &items {
        match item {
            Item::Face(k) => {
                if let Some(corners) = faces[k] {
                    let [i, j, l] = model.faces[k].map(|i| smooth[i as usize]);
                    draw_face(&mut canvas, camera, corners, i + j + l, light);
                }
            }
            Item::Normal(k) => {
                if let Some(corners) = faces[k] {
                    draw_normal(&mut canvas, camera, corners, style.line_width);
                }
            }
            Item::Obstacle(k) => {
                if let Some(&Shape::Sphere { centre, radius }) = snapshot.colliders.get(k) {
                    scenery::sphere(&mut canvas, camera, centre, radius);
                }
            }
            Item::Rod(k) => {
                let [i, j] = model.rods[k];
                if let (Some(a), Some(b)) = (at(i), at(j)) {
                    if let Some((a, b)) = clip::segment(camera.view(a), camera.view(b), near) {
                        let (a, b) = (camera.to_pixels(a), camera.to_pixels(b));
                        canvas.line_alpha(a, b, ROD, 1.8 * style.line_width, 255);
                    }
                }
            }
            Item::Spring(k) => {
                let [i, j] = model.springs[k];
                if let (Some(a), Some(b)) = (at(i), at(j)) {
                    let rest = model.rest_length.get(k).copied().unwrap_or(Real::NAN);
                    let phase = model.muscle_phase.get(k).copied().unwrap_or(Real::NAN);
                    let colour = if phase.is_nan() {
                        style
                            .strain
                            .colour(StrainColours::strain(a.distance(b), rest))
                    } else {
                        phase_colour(phase)
                    };
                    if let Some((a, b)) = clip::segment(camera.view(a), camera.view(b), near) {
                        let (a, b) = (camera.to_pixels(a), camera.to_pixels(b));
                        let alpha = if surface.on_face(i) || surface.on_face(j) {
                            // Short springs over a surface fade, so a fine
                            // mesh tints the surface rather than hiding it.
                            let pixels = (a.0 - b.0).hypot(a.1 - b.1);
                            let fade = (pixels / FADE_PIXELS).clamp(MIN_FADE, 1.0);
                            (f32::from(spring_alpha) * fade).round() as u8
                        } else {
                            255
                        };
                        canvas.line_alpha(a, b, colour, spring_width, alpha);
                    }
                }
            }
        }
    }
    let path: Vec<(f32, f32)> = trace
        .iter()
        .filter(|p| p.is_finite())
        .filter_map(|&p| project(p))
        .collect();
    for pair in path.windows(2) {
        canvas.line_alpha(pair[0], pair[1], TRACE, style.line_width, 255);
    }
    let radius = 1.1 * style.line_width;
    for i in 0..position.len() {
        if !surface.on_face(i as u32) {
            if let Some(centre) = at(i as u32).and_then(project) {
                canvas.dot(centre, radius, PARTICLE);
            }
        }
    }
    for (i, _) in model.pinned.iter().enumerate().filter(|(_, &p)| p) {
        if let Some(centre) = at(i as u32).and_then(project) {
            canvas.square(centre, style.pin_size, PIN);
        }
    }
    Ok(canvas.into_image())
}

/// Unit vector towards the light: up, a little left and behind the camera.
fn light_direction(camera: &Camera) -> Vec3 {
    let (right, up, back) = camera.axes();
    (-0.3 * right + 0.7 * up + 0.65 * back).normalize()
}

/// Fill a face, lit through `smooth` (the sum of its corners' mean
/// normals; smoother than the face's own normal, which shows the facets).
fn draw_face(
    canvas: &mut Canvas,
    camera: &Camera,
    [a, b, c]: [Vec3; 3],
    smooth: Vec3,
    light: Vec3,
) {
    let Some(normal) = (b - a).cross(c - a).try_normalize() else {
        return;
    };
    let towards_viewer = camera.towards_viewer((a + b + c) / 3.0);
    let front = normal.dot(towards_viewer) >= 0.0;
    let lit_normal = smooth
        .try_normalize()
        .filter(|s| s.dot(normal) > 0.0)
        .unwrap_or(normal);
    let (normal, colour) = if front {
        (lit_normal, FRONT)
    } else {
        (-lit_normal, BACK)
    };
    let lit = AMBIENT + (1.0 - AMBIENT) * normal.dot(light).max(0.0);
    let corners: Vec<ViewPoint> = [a, b, c].iter().map(|&p| camera.view(p)).collect();
    let visible = clip::polygon(&corners, camera.near());
    let pixels: Vec<(f32, f32)> = visible.iter().map(|&v| camera.to_pixels(v)).collect();
    canvas.polygon(&pixels, shade(colour, lit), true);
}

/// The outward normal (counter-clockwise side) from the face's centre,
/// as long as 0.8 × the square root of its area.
fn draw_normal(canvas: &mut Canvas, camera: &Camera, [a, b, c]: [Vec3; 3], width: f32) {
    let cross = (b - a).cross(c - a);
    let Some(normal) = cross.try_normalize() else {
        return;
    };
    let length = 0.8 * (0.5 * cross.length()).sqrt();
    let centre = (a + b + c) / 3.0;
    draw_segment(
        canvas,
        camera,
        centre,
        centre + length * normal,
        NORMAL,
        0.8 * width,
    );
}

fn draw_segment(
    canvas: &mut Canvas,
    camera: &Camera,
    a: Vec3,
    b: Vec3,
    colour: [u8; 3],
    width: f32,
) {
    if let Some((a, b)) = clip::segment(camera.view(a), camera.view(b), camera.near()) {
        canvas.line(camera.to_pixels(a), camera.to_pixels(b), colour, width);
    }
}

/// Which particles lie on faces, and which pairs are face edges.
struct Surface {
    on_face: Vec<bool>,
    edges: BTreeSet<(u32, u32)>,
}

impl Surface {
    fn of(faces: &[[u32; 3]], particles: usize) -> Self {
        let mut on_face = vec![false; particles];
        let mut edges = BTreeSet::new();
        for &[a, b, c] in faces {
            for (i, j) in [(a, b), (b, c), (c, a)] {
                if let Some(flag) = on_face.get_mut(i as usize) {
                    *flag = true;
                }
                edges.insert((i.min(j), i.max(j)));
            }
        }
        Surface { on_face, edges }
    }

    fn on_face(&self, i: u32) -> bool {
        self.on_face.get(i as usize).copied().unwrap_or(false)
    }

    /// A spring shown by default: along a face edge, or touching no face.
    fn shows(&self, i: u32, j: u32) -> bool {
        self.edges.contains(&(i.min(j), i.max(j))) || !(self.on_face(i) || self.on_face(j))
    }
}
