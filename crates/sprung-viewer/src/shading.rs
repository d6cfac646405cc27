//! Shaded triangles for the 3D view, lit on the CPU (macroquad's default
//! pipeline draws vertex colours): a key light from above and behind the
//! viewer, a headlight, a little specular, and surfaces lit on the side
//! facing the eye (cloth has two sides). Bodies' faces are smooth-shaded;
//! particles and sphere colliders are UV spheres; everything goes out in
//! batches that fit a draw call.

use macroquad::color::Color;
use macroquad::math::{vec2, vec3, Vec3};
use macroquad::models::{draw_mesh, Mesh, Vertex};

use crate::palette;

/// Most vertices and indices per draw call (within the capacities set in
/// `main`).
const VERTICES_PER_CALL: usize = 9000;
const INDICES_PER_CALL: usize = 27_000;

/// Where the eye and the key light are.
#[derive(Debug, Clone, Copy)]
pub struct Light {
    /// The camera's position (m).
    pub eye: Vec3,
    /// Unit direction towards the key light.
    pub key: Vec3,
}

impl Light {
    /// A light above and behind a camera at `eye` looking at `target`.
    pub fn behind(eye: Vec3, target: Vec3) -> Light {
        let key = (eye - target).normalize_or_zero() + vec3(0.0, 1.2, 0.0);
        Light {
            eye,
            key: key.normalize_or_zero(),
        }
    }

    /// `colour` lit at `p` with normal `n` (either way round), alpha `alpha`.
    pub fn lit(&self, colour: Color, p: Vec3, n: Vec3, alpha: f32) -> Color {
        let view = (self.eye - p).normalize_or_zero();
        let n = if n.dot(view) < 0.0 { -n } else { n };
        let diffuse = 0.22 + 0.5 * n.dot(self.key).max(0.0) + 0.33 * n.dot(view).max(0.0);
        let shine = 0.25
            * n.dot((self.key + view).normalize_or_zero())
                .max(0.0)
                .powi(24);
        let c = palette::shade(colour, diffuse, alpha);
        Color::new(c.r + shine, c.g + shine, c.b + shine, alpha)
    }
}

/// A mesh filled and drawn in batches.
#[derive(Default)]
pub struct Batch {
    mesh: Option<Mesh>,
    normals: Vec<Vec3>,
    sphere: Vec<Vec3>,
}

impl Batch {
    fn mesh(&mut self) -> Mesh {
        let mut mesh = self.mesh.take().unwrap_or(Mesh {
            vertices: Vec::new(),
            indices: Vec::new(),
            texture: None,
        });
        mesh.vertices.clear();
        mesh.indices.clear();
        mesh
    }

    fn flush(mesh: &mut Mesh) {
        if !mesh.indices.is_empty() {
            draw_mesh(mesh);
        }
        mesh.vertices.clear();
        mesh.indices.clear();
    }

    /// Smooth-shaded triangles `faces` over points `x`: each vertex lit by
    /// the mean normal of the faces around it.
    pub fn faces(&mut self, x: &[Vec3], faces: &[[u32; 3]], colour: Color, light: &Light) {
        self.normals.clear();
        self.normals.resize(x.len(), Vec3::ZERO);
        for &[a, b, c] in faces {
            let (a, b, c) = (a as usize, b as usize, c as usize);
            let n = (x[b] - x[a]).cross(x[c] - x[a]);
            for i in [a, b, c] {
                self.normals[i] += n;
            }
        }
        let mut mesh = self.mesh();
        for face in faces {
            if mesh.vertices.len() + 3 > VERTICES_PER_CALL {
                Batch::flush(&mut mesh);
            }
            for &i in face {
                let (p, n) = (x[i as usize], self.normals[i as usize].normalize_or_zero());
                mesh.indices.push(mesh.vertices.len() as u16);
                let c = light.lit(colour, p, n, 1.0);
                mesh.vertices.push(Vertex::new2(p, vec2(0.0, 0.0), c));
            }
        }
        Batch::flush(&mut mesh);
        self.mesh = Some(mesh);
    }

    /// Spheres `(centre, radius, colour)`, with alpha `alpha`.
    pub fn spheres(
        &mut self,
        items: impl IntoIterator<Item = (Vec3, f32, Color)>,
        alpha: f32,
        light: &Light,
    ) {
        const RINGS: usize = 8;
        const SLICES: usize = 12;
        if self.sphere.is_empty() {
            self.sphere = unit_sphere(RINGS, SLICES);
        }
        let unit = std::mem::take(&mut self.sphere);
        let mut mesh = self.mesh();
        for (centre, radius, colour) in items {
            let indices = 6 * RINGS * SLICES;
            if mesh.vertices.len() + unit.len() > VERTICES_PER_CALL
                || mesh.indices.len() + indices > INDICES_PER_CALL
            {
                Batch::flush(&mut mesh);
            }
            let first = mesh.vertices.len() as u16;
            for &n in &unit {
                let p = centre + n * radius;
                let c = light.lit(colour, p, n, alpha);
                mesh.vertices.push(Vertex::new2(p, vec2(0.0, 0.0), c));
            }
            for ring in 0..RINGS {
                for slice in 0..SLICES {
                    let at = |r: usize, s: usize| first + (r * (SLICES + 1) + s) as u16;
                    let (a, b) = (at(ring, slice), at(ring, slice + 1));
                    let (c, d) = (at(ring + 1, slice), at(ring + 1, slice + 1));
                    mesh.indices.extend_from_slice(&[a, c, b, b, c, d]);
                }
            }
        }
        Batch::flush(&mut mesh);
        self.mesh = Some(mesh);
        self.sphere = unit;
    }
}

/// Points of a unit UV sphere: `rings + 1` rows of `slices + 1` (the seam
/// repeated), pole to pole.
fn unit_sphere(rings: usize, slices: usize) -> Vec<Vec3> {
    let mut points = Vec::with_capacity((rings + 1) * (slices + 1));
    for ring in 0..=rings {
        let (sin_t, cos_t) = (std::f32::consts::PI * ring as f32 / rings as f32).sin_cos();
        for slice in 0..=slices {
            let (sin_p, cos_p) = (std::f32::consts::TAU * slice as f32 / slices as f32).sin_cos();
            points.push(vec3(sin_t * cos_p, cos_t, sin_t * sin_p));
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_sphere_points_are_unit() {
        let points = unit_sphere(8, 12);
        assert_eq!(points.len(), 9 * 13);
        assert!(points.iter().all(|p| (p.length() - 1.0).abs() < 1e-5));
    }

    #[test]
    fn both_sides_are_lit_alike() {
        let light = Light::behind(vec3(0.0, 0.0, 5.0), Vec3::ZERO);
        let colour = palette::body(0);
        let front = light.lit(colour, Vec3::ZERO, Vec3::Z, 1.0);
        let back = light.lit(colour, Vec3::ZERO, -Vec3::Z, 1.0);
        assert_eq!(front, back);
        let edge_on = light.lit(colour, Vec3::ZERO, Vec3::X, 1.0);
        assert!(front.r > edge_on.r);
    }
}
