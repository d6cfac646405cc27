//! `[wind]`: the wind that blows on every surface (docs/physics.md §3).
//!
//! Keys: `velocity` (m/s), `model` = `"simple"` (default; `coefficient`,
//! N·s/m, default 1) or `"area"` (`air_density`, kg/m³, default 1.2, and
//! `lift`, default 0), `gust = { amplitude, period }` (relative strength in
//! [0, 1], s), `turbulence = { amplitude, length_scale, time_scale }` (m/s,
//! m, s) and `seed` (default 1) for the gusts and turbulence.

use sprung::forces::{Gusts, Turbulence, Wind, WindField, WindModel, AIR_DENSITY};

use super::tables::WindTable;
use super::{positive, vector, KeyError};

/// The wind force a `[wind]` table describes.
pub(crate) fn wind(table: &WindTable) -> Result<Wind, KeyError> {
    let velocity = vector("velocity", &table.velocity)?;
    let model = match table.model.as_deref().unwrap_or("simple") {
        "simple" => {
            if let Some(key) = [
                ("air_density", table.air_density.is_some()),
                ("lift", table.lift.is_some()),
            ]
            .into_iter()
            .find_map(|(key, given)| given.then_some(key))
            {
                return Err((key, format!("`{key}` belongs to the \"area\" wind model")));
            }
            WindModel::Simple {
                coefficient: table.coefficient.unwrap_or(1.0),
            }
        }
        "area" => {
            if table.coefficient.is_some() {
                return Err((
                    "coefficient",
                    "`coefficient` belongs to the \"simple\" wind model".into(),
                ));
            }
            WindModel::Area {
                air_density: table.air_density.unwrap_or(AIR_DENSITY),
                lift: table.lift.unwrap_or(0.0),
            }
        }
        other => {
            return Err((
                "model",
                format!("unknown wind model \"{other}\" (known: simple, area)"),
            ))
        }
    };
    let gusts = match &table.gust {
        None => None,
        Some(g) => {
            if !(g.amplitude.is_finite() && (0.0..=1.0).contains(&g.amplitude)) {
                return Err((
                    "gust",
                    format!("`gust.amplitude` = {}: must be in [0, 1]", g.amplitude),
                ));
            }
            let period = positive("gust", g.period, "the gust period must be positive (s)")?;
            Some(Gusts {
                amplitude: g.amplitude,
                period,
            })
        }
    };
    let turbulence = match &table.turbulence {
        None => None,
        Some(t) => {
            if !(t.amplitude.is_finite() && t.amplitude >= 0.0) {
                return Err((
                    "turbulence",
                    format!(
                        "`turbulence.amplitude` = {}: must be finite and not negative (m/s)",
                        t.amplitude
                    ),
                ));
            }
            Some(Turbulence {
                amplitude: t.amplitude,
                length_scale: positive(
                    "turbulence",
                    t.length_scale,
                    "the length scale must be positive (m)",
                )?,
                time_scale: positive(
                    "turbulence",
                    t.time_scale,
                    "the time scale must be positive (s)",
                )?,
            })
        }
    };
    let field = WindField::varying(velocity, gusts, turbulence, table.seed.unwrap_or(1));
    Wind::new(field, model).map_err(|e| (super::body::key_of(&e), e.to_string()))
}
