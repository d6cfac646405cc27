//! How the world is seen: an orthographic view of the xy-plane for 2D
//! scenes, an orbit camera for 3D ones. Both map world points to screen
//! pixels and the cursor back into the world, for picking and dragging.

use macroquad::math::{vec2, vec3, vec4, Mat4, Rect, Vec2, Vec3};
use macroquad::prelude::Camera3D;

/// An engine vector as a drawing one.
pub fn to_f32(p: sprung::Vec3) -> Vec3 {
    vec3(p.x as f32, p.y as f32, p.z as f32)
}

/// A drawing vector as an engine one.
pub fn to_f64(p: Vec3) -> sprung::Vec3 {
    sprung::Vec3::new(p.x as f64, p.y as f64, p.z as f64)
}

/// An axis-aligned box (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Smallest corner.
    pub min: Vec3,
    /// Largest corner.
    pub max: Vec3,
}

impl Bounds {
    /// The box around `points`; a unit box about the origin when empty.
    pub fn of(points: impl IntoIterator<Item = Vec3>) -> Self {
        let (min, max) = points.into_iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        );
        if min.x > max.x {
            Bounds {
                min: Vec3::splat(-0.5),
                max: Vec3::splat(0.5),
            }
        } else {
            Bounds { min, max }
        }
    }

    /// Centre.
    pub fn centre(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Half the diagonal, at least 0.25 m.
    pub fn radius(&self) -> f32 {
        (0.5 * (self.max - self.min).length()).max(0.25)
    }
}

/// Orthographic view of the xy-plane (2D scenes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flat {
    /// World point at the centre of the viewport (m).
    pub centre: Vec2,
    /// Pixels per metre.
    pub scale: f32,
}

/// A camera orbiting a target point (3D scenes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orbit {
    /// The point looked at (m).
    pub target: Vec3,
    /// Angle about the vertical axis (rad).
    pub yaw: f32,
    /// Angle above the horizontal (rad).
    pub pitch: f32,
    /// Distance from the target (m).
    pub distance: f32,
}

/// Vertical field of view of the orbit camera (rad).
const FOVY: f32 = 0.8;

/// A view of the world in a viewport of the screen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum View {
    /// 2D.
    Flat(Flat),
    /// 3D.
    Orbit(Orbit),
}

impl View {
    /// A view framing `bounds` in `viewport` (pixels).
    pub fn framing(flat: bool, bounds: Bounds, viewport: Rect) -> View {
        let centre = bounds.centre();
        if flat {
            let size = (bounds.max - bounds.min).truncate().max(Vec2::splat(0.5));
            let scale = (viewport.w / size.x).min(viewport.h / size.y) / 1.4;
            View::Flat(Flat {
                centre: centre.truncate(),
                scale,
            })
        } else {
            View::Orbit(Orbit {
                target: centre,
                yaw: 0.6,
                pitch: 0.35,
                distance: 1.6 * bounds.radius() / (0.5 * FOVY).tan(),
            })
        }
    }

    /// The macroquad camera drawing 3D into `viewport`; `None` for 2D.
    pub fn camera(&self, viewport: Rect, dpi: f32) -> Option<Camera3D> {
        let View::Orbit(orbit) = self else {
            return None;
        };
        Some(Camera3D {
            position: orbit.position(),
            target: orbit.target,
            up: Vec3::Y,
            fovy: FOVY,
            aspect: Some(viewport.w / viewport.h.max(1.0)),
            viewport: Some((
                (viewport.x * dpi) as i32,
                0,
                (viewport.w * dpi) as i32,
                (viewport.h * dpi) as i32,
            )),
            z_near: 0.01 * orbit.distance,
            z_far: 100.0 * orbit.distance,
            ..Default::default()
        })
    }

    /// Screen position (pixels) of world point `p` and its depth (distance
    /// along the view, m; 0 in 2D), or `None` behind the camera.
    pub fn project(&self, p: Vec3, viewport: Rect) -> Option<(Vec2, f32)> {
        match self {
            View::Flat(flat) => Some((flat.to_screen(p.truncate(), viewport), 0.0)),
            View::Orbit(orbit) => {
                let clip = orbit.matrix(viewport) * vec4(p.x, p.y, p.z, 1.0);
                if clip.w <= 1e-6 {
                    return None;
                }
                let ndc = clip.truncate() / clip.w;
                let screen = vec2(
                    viewport.x + 0.5 * (ndc.x + 1.0) * viewport.w,
                    viewport.y + 0.5 * (1.0 - ndc.y) * viewport.h,
                );
                Some((screen, clip.w))
            }
        }
    }

    /// The world point under the cursor `screen` on the plane through
    /// `through` facing the camera (the xy-plane in 2D).
    pub fn cursor_point(&self, screen: Vec2, through: Vec3, viewport: Rect) -> Vec3 {
        match self {
            View::Flat(flat) => flat.to_world(screen, viewport).extend(0.0),
            View::Orbit(orbit) => {
                let (origin, direction) = orbit.ray(screen, viewport);
                let normal = (orbit.target - orbit.position()).normalize_or_zero();
                let denominator = direction.dot(normal);
                if denominator.abs() < 1e-6 {
                    return through;
                }
                let t = (through - origin).dot(normal) / denominator;
                origin + direction * t.max(0.0)
            }
        }
    }

    /// Pixels per metre at depth `depth` (for sizes drawn in screen space).
    pub fn pixels_per_metre(&self, depth: f32, viewport: Rect) -> f32 {
        match self {
            View::Flat(flat) => flat.scale,
            View::Orbit(_) => viewport.h / (2.0 * depth.max(1e-3) * (0.5 * FOVY).tan()),
        }
    }

    /// Zoom in (`steps` > 0) or out about the viewport centre.
    pub fn zoom(&mut self, steps: f32) {
        let factor = 1.15_f32.powf(steps);
        match self {
            View::Flat(flat) => flat.scale *= factor,
            View::Orbit(orbit) => orbit.distance /= factor,
        }
    }

    /// Turn the orbit camera (rad), or, in 2D, pan by `pixels`.
    pub fn drag(&mut self, pixels: Vec2) {
        match self {
            View::Flat(flat) => flat.centre += vec2(-pixels.x, pixels.y) / flat.scale,
            View::Orbit(orbit) => {
                orbit.yaw -= 0.008 * pixels.x;
                orbit.pitch = (orbit.pitch + 0.008 * pixels.y).clamp(-1.5, 1.5);
            }
        }
    }

    /// Move the target (3D) or the centre (2D) by `pixels` on the screen.
    pub fn pan(&mut self, pixels: Vec2, viewport: Rect) {
        match self {
            View::Flat(_) => self.drag(pixels),
            View::Orbit(orbit) => {
                let scale = orbit.distance * 2.0 * (0.5 * FOVY).tan() / viewport.h;
                let forward = (orbit.target - orbit.position()).normalize_or_zero();
                let right = forward.cross(Vec3::Y).normalize_or_zero();
                let up = right.cross(forward);
                orbit.target += (-pixels.x * right + pixels.y * up) * scale;
            }
        }
    }

    /// Follow bodies that leave the middle of the view (`bounds` reaching
    /// past 85 % of it): move towards their centre by a tenth a frame, and
    /// widen (5 % a frame at most) when they no longer fit.
    pub fn follow(&mut self, bounds: Bounds, viewport: Rect) {
        const MARGIN: f32 = 0.85;
        let (outside, need) = match self {
            View::Flat(flat) => {
                let half = vec2(viewport.w, viewport.h) / (2.0 * flat.scale);
                let reach = (bounds.min.truncate() - flat.centre)
                    .abs()
                    .max((bounds.max.truncate() - flat.centre).abs());
                let size = 0.5 * (bounds.max - bounds.min).truncate();
                let outside = reach.x > MARGIN * half.x || reach.y > MARGIN * half.y;
                (outside, (size.x / half.x).max(size.y / half.y) / MARGIN)
            }
            View::Orbit(orbit) => {
                let visible = orbit.distance * (0.5 * FOVY).tan();
                let reach = (bounds.min - orbit.target)
                    .length()
                    .max((bounds.max - orbit.target).length());
                (
                    reach > visible / MARGIN,
                    bounds.radius() / (MARGIN * visible),
                )
            }
        };
        if !outside {
            return;
        }
        let factor = if need.is_finite() {
            need.clamp(1.0, 1.05)
        } else {
            1.0
        };
        let centre = bounds.centre();
        match self {
            View::Flat(flat) => {
                flat.centre += 0.1 * (centre.truncate() - flat.centre);
                flat.scale /= factor;
            }
            View::Orbit(orbit) => {
                orbit.target += 0.1 * (centre - orbit.target);
                orbit.distance *= factor;
            }
        }
    }
}

impl Flat {
    fn to_screen(self, p: Vec2, viewport: Rect) -> Vec2 {
        let centre = viewport.center();
        centre + vec2(p.x - self.centre.x, self.centre.y - p.y) * self.scale
    }

    fn to_world(self, screen: Vec2, viewport: Rect) -> Vec2 {
        let d = (screen - viewport.center()) / self.scale;
        self.centre + vec2(d.x, -d.y)
    }
}

impl Orbit {
    /// Where the camera is (m).
    pub fn position(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * vec3(cp * sy, sp, cp * cy)
    }

    /// Projection times view, as `Camera3D` makes it (without asking the
    /// window for its size).
    fn matrix(&self, viewport: Rect) -> Mat4 {
        let aspect = viewport.w / viewport.h.max(1.0);
        Mat4::perspective_rh_gl(FOVY, aspect, 0.01 * self.distance, 100.0 * self.distance)
            * Mat4::look_at_rh(self.position(), self.target, Vec3::Y)
    }

    /// The cursor ray: origin and unit direction.
    fn ray(&self, screen: Vec2, viewport: Rect) -> (Vec3, Vec3) {
        let ndc = vec2(
            2.0 * (screen.x - viewport.x) / viewport.w - 1.0,
            1.0 - 2.0 * (screen.y - viewport.y) / viewport.h,
        );
        let inverse = self.matrix(viewport).inverse();
        let near = inverse.project_point3(ndc.extend(-1.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        (near, (far - near).normalize_or_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const VIEWPORT: Rect = Rect {
        x: 300.0,
        y: 0.0,
        w: 900.0,
        h: 700.0,
    };

    fn bounds() -> Bounds {
        Bounds::of([vec3(-1.0, 0.0, -0.5), vec3(2.0, 1.5, 0.5)])
    }

    #[test]
    fn flat_cursor_round_trip() {
        let view = View::framing(true, bounds(), VIEWPORT);
        let p = vec3(0.7, 0.3, 0.0);
        let (screen, _) = view.project(p, VIEWPORT).unwrap_or_default();
        let back = view.cursor_point(screen, Vec3::ZERO, VIEWPORT);
        assert!((back - p).length() < 1e-4, "{back}");
    }

    #[test]
    fn orbit_cursor_round_trip_on_the_view_plane() {
        let view = View::framing(false, bounds(), VIEWPORT);
        let p = bounds().centre() + vec3(0.2, -0.1, 0.0);
        let (screen, depth) = view.project(p, VIEWPORT).unwrap_or_default();
        assert!(depth > 0.0);
        assert!(VIEWPORT.contains(screen), "{screen}");
        let back = view.cursor_point(screen, p, VIEWPORT);
        assert!((back - p).length() < 1e-3, "{back} vs {p}");
    }

    #[test]
    fn follow_brings_far_bodies_into_view() {
        let mut view = View::framing(true, bounds(), VIEWPORT);
        let far = Bounds::of([vec3(-20.0, 0.0, 0.0), vec3(20.0, 1.0, 0.0)]);
        for _ in 0..200 {
            view.follow(far, VIEWPORT);
        }
        let (left, _) = view
            .project(vec3(-20.0, 0.0, 0.0), VIEWPORT)
            .unwrap_or_default();
        assert!(left.x >= VIEWPORT.x, "{left}");
        let moved = Bounds::of([vec3(30.0, 0.0, 0.0), vec3(30.5, 0.5, 0.0)]);
        for _ in 0..200 {
            view.follow(moved, VIEWPORT);
        }
        let (at, _) = view.project(moved.centre(), VIEWPORT).unwrap_or_default();
        assert!(VIEWPORT.contains(at), "{at}");
    }
}
