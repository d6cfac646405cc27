//! The tables of how bodies meet the world and each other:
//! `[[collider]]`, `[contact]` and `[gravitation]`.

use sprung::forces::{Gravitation, GRAVITATIONAL_CONSTANT};
use sprung::{colliders, Collider, ContactResponse, ContactSettings, Shape};

use super::tables::{self, ColliderTable};
use super::{body, vector, KeyError};

pub(super) fn collider(table: &ColliderTable) -> Result<Collider, KeyError> {
    let shape = match (&table.plane, &table.sphere) {
        (Some(_), Some(_)) => {
            return Err(("sphere", "a collider is a `plane` or a `sphere`, not both".into()));
        }
        (Some(plane), None) => {
            let point = vector("plane", &plane.point)?;
            let normal = vector("plane", &plane.normal)?;
            Shape::plane(point, normal).map_err(|e| ("plane", e.to_string()))?
        }
        (None, Some(sphere)) => {
            let centre = vector("sphere", &sphere.centre)?;
            Shape::sphere(centre, sphere.radius).map_err(|e| ("sphere", e.to_string()))?
        }
        (None, None) => {
            return Err((
                "plane",
                "a collider needs a shape: `plane = { point, normal }` or `sphere = { centre, radius }`".into(),
            ))
        }
    };
    let friction = table.friction.unwrap_or(0.0);
    let response = match table.penalty_stiffness {
        Some(stiffness) => {
            if table.restitution.is_some() {
                return Err((
                    "restitution",
                    "`restitution` belongs to the projection form; the penalty form (`penalty_stiffness`) bounces through its spring".into(),
                ));
            }
            ContactResponse::Penalty {
                stiffness,
                damping: table.penalty_damping.unwrap_or(0.0),
                friction,
            }
        }
        None => {
            if table.penalty_damping.is_some() {
                return Err((
                    "penalty_damping",
                    "`penalty_damping` needs `penalty_stiffness`".into(),
                ));
            }
            ContactResponse::Projection {
                restitution: table.restitution.unwrap_or(0.0),
                friction,
            }
        }
    };
    let mut collider =
        Collider::new(shape, response).map_err(|e| (body::key_of(&e), e.to_string()))?;
    if let Some(keyframes) = &table.path {
        let keyframes = keyframes
            .iter()
            .map(|k| match k.as_slice() {
                [t, rest @ ..] => Ok((*t, vector("path", rest)?)),
                [] => Err((
                    "path",
                    "a `path` keyframe is [time, x, y] or [time, x, y, z]".to_string(),
                )),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let path = colliders::Path::new(keyframes).map_err(|e| ("path", e.to_string()))?;
        collider = collider.with_path(path);
    }
    Ok(collider)
}

pub(super) fn contact(
    table: &tables::ContactTable,
    limits: &sprung::world::Settings,
) -> Result<ContactSettings, KeyError> {
    let defaults = ContactSettings::default();
    let settings = ContactSettings {
        enabled: table.enabled.unwrap_or(defaults.enabled),
        thickness: table.thickness.unwrap_or(defaults.thickness),
        friction: table.friction.unwrap_or(defaults.friction),
        stiffness: table.stiffness,
        damping: table.damping,
        ccd: table.ccd.unwrap_or(defaults.ccd),
    };
    settings
        .validate_within(limits.max_distance, limits.max_speed)
        .map_err(|e| {
            let key = match body::key_of(&e) {
                k if k.starts_with("contact.") => &k["contact.".len()..],
                k => k,
            };
            (key, e.to_string())
        })?;
    Ok(settings)
}

/// The `[gravitation]` force: `constant` (N·m²/kg², default
/// [`GRAVITATIONAL_CONSTANT`]) and `softening` (m, default 0).
pub(super) fn gravitation(table: &tables::GravitationTable) -> Result<Gravitation, KeyError> {
    Gravitation::new(
        table.constant.unwrap_or(GRAVITATIONAL_CONSTANT),
        table.softening.unwrap_or(0.0),
    )
    .map_err(|e| {
        let key = match body::key_of(&e) {
            k if k.starts_with("gravitation.") => &k["gravitation.".len()..],
            k => k,
        };
        (key, e.to_string())
    })
}
