//! An icosphere: the icosahedron with each triangle split in four
//! `subdivisions` times and every vertex pushed onto the sphere.
//! `10 · 4ˢ + 2` vertices: 12, 42, 162, 642, 2562, 10242, ...

use super::{check_length, refine, surface, SurfaceSprings};
use crate::body::BodyData;
use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// Most subdivisions accepted (7 gives 163 842 vertices).
pub const MAX_SUBDIVISIONS: usize = 7;

/// A closed sphere of `radius` (m) centred on the origin, triangulated as an
/// icosphere with `subdivisions` levels, faces counter-clockwise seen from
/// outside, springs on every edge and, per `springs`, across every pair of
/// adjacent triangles and to a centre particle.
///
/// # Examples
///
/// Each subdivision splits every triangle in four: `s` of them give
/// `10 · 4ˢ + 2` vertices, `20 · 4ˢ` faces and `30 · 4ˢ` edges, and a
/// bending spring across each edge doubles the springs:
///
/// ```
/// use sprung::build::{self, SurfaceSprings};
///
/// for s in 0..3 {
///     let sphere = build::icosphere(2.0, s, SurfaceSprings::default()).unwrap();
///     let four = 4_usize.pow(s as u32);
///     assert_eq!(sphere.particle_count(), 10 * four + 2);
///     assert_eq!(sphere.faces.len(), 20 * four);
///     assert_eq!(sphere.springs.len(), 2 * 30 * four);
///     assert!(sphere.is_closed());
///     // On the sphere, to the rounding of the normalised vertices.
///     assert!(sphere.position.iter().all(|p| (p.length() - 2.0).abs() < 1e-15));
/// }
/// ```
pub fn icosphere(
    radius: Real,
    subdivisions: usize,
    springs: SurfaceSprings,
) -> Result<BodyData, BuildError> {
    check_length("sphere.radius", radius)?;
    if subdivisions > MAX_SUBDIVISIONS {
        return Err(BuildError::OutOfRange {
            field: "sphere.subdivisions",
            value: subdivisions as Real,
            reason: "at most 7 subdivisions (163 842 vertices)",
        });
    }
    let (mut points, mut faces) = icosahedron();
    for _ in 0..subdivisions {
        faces = refine(&mut points, &faces);
    }
    let position = points.into_iter().map(|p| radius * p.normalize()).collect();
    surface(position, faces, springs)
}

/// The unit-circumradius icosahedron, faces turned outward.
#[rustfmt::skip]
fn icosahedron() -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let phi = (1.0 + 5.0_f64.sqrt()) / 2.0;
    let points: Vec<Vec3> = [
        (-1.0, phi, 0.0), (1.0, phi, 0.0), (-1.0, -phi, 0.0), (1.0, -phi, 0.0),
        (0.0, -1.0, phi), (0.0, 1.0, phi), (0.0, -1.0, -phi), (0.0, 1.0, -phi),
        (phi, 0.0, -1.0), (phi, 0.0, 1.0), (-phi, 0.0, -1.0), (-phi, 0.0, 1.0),
    ]
    .into_iter()
    .map(|(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces = vec![
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    for face in &mut faces {
        let [a, b, c] = face.map(|i| points[i]);
        if (b - a).cross(c - a).dot(a + b + c) < 0.0 {
            face.swap(1, 2);
        }
    }
    (points, faces)
}
