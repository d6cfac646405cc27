//! The control panel on the left: scene picker, run controls, integrator
//! and time step, the physical sliders, display toggles and the strain
//! legend. Every control has a key too (shown in its label).

use macroquad::math::Rect;
use sprung::Real;

use crate::app::{cycle_integrator, scale_dt, App};
use crate::demos::Source;
use crate::palette;
use crate::render::{legend, FONT};
use crate::sim::Sim;
use sprung_io::demos::DEMOS;

/// Draw the panel of `app` in `area` and act on its controls.
pub fn draw(app: &mut App, area: Rect) {
    let mut ui = std::mem::take(&mut app.ui);
    ui.begin(area);
    ui.text("sprung", FONT + 8.0, palette::TEXT);
    ui.text("mass-spring-damper viewer", FONT - 4.0, palette::DIM);
    ui.gap(6.0);
    let label = app.source.short_label();
    match ui.stepper("scene", &short(&label, 20)) {
        0 => {}
        step => app.next_scene(step),
    }
    if ui.buttons(&["all scenes (Tab)"], &[app.scene_list]) == Some(0) {
        app.scene_list = !app.scene_list;
    }
    if app.scene_list {
        let current = app.source.demo();
        for (row, pair) in DEMOS.chunks(2).enumerate() {
            let names: Vec<&str> = pair.iter().map(|d| d.name).collect();
            let on: Vec<bool> = (0..pair.len())
                .map(|k| current == Some(2 * row + k))
                .collect();
            if let Some(k) = ui.buttons(&names, &on) {
                app.open(Source::Demo(2 * row + k), None);
                app.scene_list = false;
            }
        }
        // The list stands in for the controls until a scene is picked.
        app.ui = ui;
        return;
    }
    ui.rule();
    let Some(sim) = app.sim.as_mut() else {
        app.ui = ui;
        return;
    };
    let pause = if sim.paused { "run" } else { "pause" };
    match ui.buttons(
        &[pause, "step (S)", "reset (R)"],
        &[sim.paused, false, false],
    ) {
        Some(0) => sim.paused = !sim.paused,
        Some(1) => {
            sim.paused = true;
            if sim.failure.is_none() {
                sim.step_once();
            }
        }
        Some(2) => {
            app.ui = ui;
            app.reset();
            return;
        }
        _ => {}
    }
    match ui.stepper("integrator", sim.settings.integrator.name()) {
        0 => {}
        step => cycle_integrator(sim, step),
    }
    match ui.stepper("dt  [ ]", &format!("{:.2e} s", sim.settings.dt)) {
        0 => {}
        step => scale_dt(sim, if step < 0 { 0.5 } else { 2.0 }),
    }
    let stable = sim.world.stable_time_step();
    let colour = if sim.settings.dt > stable {
        palette::ERROR
    } else {
        palette::DIM
    };
    ui.pair("stable dt (explicit)", &format!("{stable:.2e} s"), colour);
    ui.gap(6.0);
    sliders(&mut ui, sim);
    ui.rule();
    let poke = app.hand.poke.is_some();
    let toggles = ["poke (P)", "springs (W)", "faces (F)"];
    match ui.buttons(&toggles, &[poke, app.look.springs, app.look.faces]) {
        Some(0) => app.toggle_poke(),
        Some(1) => app.look.springs = !app.look.springs,
        Some(2) => app.look.faces = !app.look.faces,
        _ => {}
    }
    ui.gap(10.0);
    let at = ui.cursor();
    legend(
        at.x,
        at.y,
        area.w - 2.0 * (at.x - area.x),
        app.look.full_strain,
    );
    app.ui = ui;
}

/// The physical settings: speed, stiffness, damping, gas and wind.
fn sliders(ui: &mut crate::ui::Ui, sim: &mut Sim) {
    let mut s = sim.settings;
    let mut changed = false;
    let mut t = to_unit(s.speed.log10(), -1.3, 0.0);
    if ui.slider("speed", &format!("{:.2}x", s.speed), &mut t, true) {
        s.speed = 10f64.powf(from_unit(t, -1.3, 0.0));
    }
    let mean_k = mean(&sim.world.springs.stiffness);
    let mut t = to_unit(s.stiffness_scale.log10(), -1.0, 1.0);
    let text = format!("x{:.2}  {}", s.stiffness_scale, si(mean_k, "N/m"));
    if ui.slider("stiffness", &text, &mut t, true) {
        s.stiffness_scale = 10f64.powf(from_unit(t, -1.0, 1.0));
        changed = true;
    }
    let mean_c = mean(&sim.world.springs.damping);
    let factor = sim.damping_is_factor();
    let top = if factor { 5.0 } else { 2.0 * critical(sim) };
    let mut t = to_unit((s.damping / top).sqrt(), 0.0, 1.0);
    let text = if factor {
        format!("x{:.2}  {}", s.damping, si(mean_c, "N·s/m"))
    } else {
        si(mean_c, "N·s/m")
    };
    if ui.slider("damping", &text, &mut t, true) {
        s.damping = top * from_unit(t, 0.0, 1.0).powi(2);
        changed = true;
    }
    let gas = sim.has_gas();
    let mut t = to_unit(s.nrt_scale, 0.0, 3.0);
    let text = if gas {
        format!("x{:.2}", s.nrt_scale)
    } else {
        "no gas".into()
    };
    if ui.slider("gas nRT", &text, &mut t, gas) {
        s.nrt_scale = from_unit(t, 0.0, 3.0);
        changed = true;
    }
    let wind = sim.has_wind();
    let top = (3.0 * sim.defaults.wind_speed).max(10.0);
    let mut t = to_unit(s.wind_speed, 0.0, top);
    let text = if wind {
        format!("{:.1} m/s", s.wind_speed)
    } else {
        "no wind".into()
    };
    if ui.slider("wind", &text, &mut t, wind) {
        s.wind_speed = from_unit(t, 0.0, top);
        changed = true;
    }
    if ui.buttons(&["scene's settings"], &[]) == Some(0) {
        s = sim.defaults;
        changed = true;
    }
    sim.settings = s;
    if changed {
        sim.apply();
    }
}

/// `value` in `[low, high]` as a slider position in [0, 1].
pub fn to_unit(value: Real, low: Real, high: Real) -> f32 {
    ((value - low) / (high - low)).clamp(0.0, 1.0) as f32
}

/// A slider position `t` in [0, 1] as a value in `[low, high]`.
pub fn from_unit(t: f32, low: Real, high: Real) -> Real {
    low + (high - low) * t as Real
}

fn mean(values: &[Real]) -> Real {
    values.iter().sum::<Real>() / values.len().max(1) as Real
}

/// Critical damping `2 √(k m)` of a typical spring and particle (N·s/m).
fn critical(sim: &Sim) -> Real {
    let k = mean(&sim.world.springs.stiffness) / sim.settings.stiffness_scale.max(1e-9);
    let m = mean(&sim.world.particles.mass);
    (2.0 * (k * m).sqrt()).max(1e-3)
}

/// A number with three significant digits and its unit.
fn si(value: Real, unit: &str) -> String {
    if value == 0.0 || (1e-2..1e4).contains(&value.abs()) {
        format!("{value:.3} {unit}")
    } else {
        format!("{value:.2e} {unit}")
    }
}

/// `text`, cut to `count` characters with an ellipsis (keeping its end: a
/// file name).
fn short(text: &str, count: usize) -> String {
    let chars: Vec<char> = text.chars().collect();
    if chars.len() <= count {
        text.to_string()
    } else {
        let tail: String = chars[chars.len() - (count - 3)..].iter().collect();
        format!("...{tail}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slider_mapping_round_trips_and_clamps() {
        for value in [-1.0, 0.0, 0.3, 1.0] {
            let t = to_unit(value, -1.0, 1.0);
            assert!((from_unit(t, -1.0, 1.0) - value).abs() < 1e-6);
        }
        assert_eq!(to_unit(5.0, 0.0, 1.0), 1.0);
        assert_eq!(to_unit(-5.0, 0.0, 1.0), 0.0);
    }

    #[test]
    fn short_keeps_the_end() {
        assert_eq!(short("ball2d", 20), "ball2d");
        assert_eq!(short("/a/very/long/path/to/scene.toml", 12), "...cene.toml");
    }
}
