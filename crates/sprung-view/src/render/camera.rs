//! The camera: an orthographic view straight down the z axis for 2D scenes
//! (every particle at z = 0 in every frame), a perspective view from an
//! elevated angle for 3D ones, framed once over all the frames of a run so
//! it does not jump ([`Camera::frame`]), or set by eye and target.

use sprung::{Real, Vec3};

use super::fit::{obstacle_points, sample_points, Fit};
use super::snapshot::Snapshot;

/// Fraction of the picture left free on each side by automatic framing.
const MARGIN: Real = 0.06;
/// Azimuth of the automatic 3D view (degrees from +z towards +x).
pub(super) const AZIMUTH_DEGREES: Real = 32.0;
/// Elevation of the automatic 3D view above the horizontal (degrees).
pub(super) const ELEVATION_DEGREES: Real = 24.0;
/// Default vertical field of view of the perspective camera (degrees).
pub const DEFAULT_FOV_DEGREES: Real = 40.0;

/// The box holding every particle of every frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Smallest x, y, z (m).
    pub min: Vec3,
    /// Largest x, y, z (m).
    pub max: Vec3,
    /// True when every particle of every frame has z = 0 (a 2D scene).
    pub planar: bool,
}

impl Bounds {
    /// The bounds of all particles of all `snapshots`, and of their
    /// sphere colliders; `None` when they hold no (finite) particle.
    /// `planar` looks at the particles only.
    pub fn of_snapshots(snapshots: &[Snapshot]) -> Option<Self> {
        let mut bounds: Option<Bounds> = None;
        for p in snapshots.iter().flat_map(|s| &s.position) {
            if !p.is_finite() {
                continue;
            }
            let b = bounds.get_or_insert(Bounds {
                min: *p,
                max: *p,
                planar: true,
            });
            b.min = b.min.min(*p);
            b.max = b.max.max(*p);
            b.planar &= p.z == 0.0;
        }
        let b = bounds.as_mut()?;
        for p in snapshots.iter().flat_map(|s| obstacle_points(&s.colliders)) {
            b.min = b.min.min(p);
            b.max = b.max.max(p);
        }
        bounds
    }

    /// The centre of the box (m).
    pub fn centre(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// The length of the box's diagonal (m).
    pub fn diagonal(&self) -> Real {
        (self.max - self.min).length()
    }
}

/// How the camera is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSetting {
    /// Where the camera stands (m); `None`: chosen to frame the bodies (2D
    /// scenes are then seen straight on, orthographic).
    pub eye: Option<Vec3>,
    /// The point looked at (m); `None`: the centre of the bodies' box.
    pub target: Option<Vec3>,
    /// Vertical field of view of the perspective camera (degrees, in
    /// (0, 180)).
    pub fov_degrees: Real,
}

impl Default for CameraSetting {
    fn default() -> Self {
        CameraSetting {
            eye: None,
            target: None,
            fov_degrees: DEFAULT_FOV_DEGREES,
        }
    }
}

/// A point as the camera sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewPoint {
    /// Right of the image centre (m at the point's depth, or m for the
    /// orthographic camera).
    pub x: Real,
    /// Up from the image centre (same units as `x`).
    pub y: Real,
    /// Distance in front of the camera along its axis (m); larger is
    /// farther.
    pub depth: Real,
}

/// The projection of a camera.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Straight down -z: x right, y up.
    Orthographic {
        /// The world point at the image centre (m).
        centre: Vec3,
        /// Pixels per metre.
        scale: Real,
    },
    /// Perspective from `eye`.
    Perspective {
        /// The camera position (m).
        eye: Vec3,
        /// Unit vector to the right of the image.
        right: Vec3,
        /// Unit vector up the image.
        up: Vec3,
        /// Unit vector along the view.
        forward: Vec3,
        /// Focal length (pixels).
        focal: Real,
        /// Nearest depth drawn (m); nearer geometry is clipped.
        near: Real,
    },
}

/// A camera with the picture size it projects onto.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// How world points map to the image.
    pub projection: Projection,
    /// Picture width (pixels).
    pub width: u32,
    /// Picture height (pixels).
    pub height: u32,
}

impl Camera {
    /// The camera for a picture of `width` × `height` pixels showing
    /// every point of `snapshots` (whose box is `bounds`), as `setting`
    /// asks: orthographic for a planar box with no eye given, else
    /// perspective from the eye given or from an elevated angle, aimed and
    /// just far enough back that every point is in the picture.
    pub fn frame(
        snapshots: &[Snapshot],
        bounds: &Bounds,
        setting: &CameraSetting,
        width: u32,
        height: u32,
    ) -> Camera {
        let (w, h) = (Real::from(width.max(1)), Real::from(height.max(1)));
        let target = setting.target.unwrap_or_else(|| bounds.centre());
        let size = bounds.diagonal().max(1e-6);
        let projection = match setting.eye {
            None if bounds.planar => {
                let half = (bounds.max - target)
                    .abs()
                    .max((bounds.min - target).abs())
                    .max(Vec3::splat(1e-3 * size));
                let free = 1.0 - 2.0 * MARGIN;
                let scale = (free * w / (2.0 * half.x)).min(free * h / (2.0 * half.y));
                Projection::Orthographic {
                    centre: target,
                    scale,
                }
            }
            eye => {
                let tan_y = (0.5 * setting.fov_degrees.to_radians()).tan();
                let focal = 0.5 * h / tan_y;
                let (eye, target) = match eye {
                    Some(eye) => (eye, target),
                    None => {
                        let free = 1.0 - 2.0 * MARGIN;
                        let points = sample_points(snapshots);
                        let fit = Fit {
                            tan_x: free * tan_y * w / h,
                            tan_y: free * tan_y,
                        };
                        fit.eye(&points, bounds, setting.target)
                    }
                };
                let (right, up, forward) = basis(eye, target);
                let near = 1e-3 * (eye.distance(target) + size);
                Projection::Perspective {
                    eye,
                    right,
                    up,
                    forward,
                    focal,
                    near,
                }
            }
        };
        Camera {
            projection,
            width,
            height,
        }
    }

    /// True for the orthographic (2D) camera.
    pub fn is_orthographic(&self) -> bool {
        matches!(self.projection, Projection::Orthographic { .. })
    }

    /// The point `p` (m) in camera coordinates.
    pub fn view(&self, p: Vec3) -> ViewPoint {
        match self.projection {
            Projection::Orthographic { centre, .. } => ViewPoint {
                x: p.x - centre.x,
                y: p.y - centre.y,
                depth: -p.z,
            },
            Projection::Perspective {
                eye,
                right,
                up,
                forward,
                ..
            } => {
                let d = p - eye;
                ViewPoint {
                    x: d.dot(right),
                    y: d.dot(up),
                    depth: d.dot(forward),
                }
            }
        }
    }

    /// The nearest depth drawn (m); `-inf` for the orthographic camera.
    pub fn near(&self) -> Real {
        match self.projection {
            Projection::Orthographic { .. } => Real::NEG_INFINITY,
            Projection::Perspective { near, .. } => near,
        }
    }

    /// The pixel position (x right, y down, pixel centres at +0.5) of a
    /// point in camera coordinates, which must be at depth ≥ [`Self::near`].
    pub fn to_pixels(&self, v: ViewPoint) -> (f32, f32) {
        let (cx, cy) = (0.5 * Real::from(self.width), 0.5 * Real::from(self.height));
        let (x, y) = match self.projection {
            Projection::Orthographic { scale, .. } => (cx + scale * v.x, cy - scale * v.y),
            Projection::Perspective { focal, .. } => {
                let f = focal / v.depth;
                (cx + f * v.x, cy - f * v.y)
            }
        };
        (x as f32, y as f32)
    }

    /// Pixels per metre at camera depth `depth` (m).
    pub fn pixels_per_metre(&self, depth: Real) -> Real {
        match self.projection {
            Projection::Orthographic { scale, .. } => scale,
            Projection::Perspective { focal, .. } => focal / depth,
        }
    }

    /// Unit vector from the world point `p` (m) towards the viewer.
    pub fn towards_viewer(&self, p: Vec3) -> Vec3 {
        match self.projection {
            Projection::Orthographic { .. } => Vec3::Z,
            Projection::Perspective { eye, forward, .. } => {
                (eye - p).try_normalize().unwrap_or(-forward)
            }
        }
    }

    /// The camera's right, up and backward (towards the viewer) unit
    /// vectors in world coordinates.
    pub fn axes(&self) -> (Vec3, Vec3, Vec3) {
        match self.projection {
            Projection::Orthographic { .. } => (Vec3::X, Vec3::Y, Vec3::Z),
            Projection::Perspective {
                right, up, forward, ..
            } => (right, up, -forward),
        }
    }
}

/// Right, up and forward unit vectors of a camera at `eye` looking at
/// `target`, with world +y up on the image (or ∓z when looking straight
/// down or up).
pub(super) fn basis(eye: Vec3, target: Vec3) -> (Vec3, Vec3, Vec3) {
    let forward = (target - eye).try_normalize().unwrap_or(Vec3::NEG_Z);
    let hint = if forward.y.abs() > 0.999 {
        if forward.y < 0.0 {
            Vec3::NEG_Z
        } else {
            Vec3::Z
        }
    } else {
        Vec3::Y
    };
    let right = forward.cross(hint).normalize();
    let up = right.cross(forward);
    (right, up, forward)
}
