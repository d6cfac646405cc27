//! Input on the world: keyboard shortcuts and the mouse (grab, drag and
//! throw a particle; orbit or pan the camera; zoom).

use macroquad::input::{
    is_key_down, is_key_pressed, is_mouse_button_down, is_mouse_button_pressed, mouse_position,
    mouse_wheel, KeyCode, MouseButton,
};
use macroquad::math::{vec2, Rect, Vec2, Vec3};

use crate::app::{cycle_integrator, scale_dt, App};
use crate::camera::View;
use crate::demos::Source;
use crate::hand::pick;

impl App {
    /// Keyboard shortcuts (every control of the panel has one).
    pub(crate) fn keys(&mut self) {
        let shift = is_key_down(KeyCode::LeftShift) || is_key_down(KeyCode::RightShift);
        let pressed = |keys: &[KeyCode]| keys.iter().any(|&k| is_key_pressed(k));
        if pressed(&[KeyCode::Tab, KeyCode::PageDown, KeyCode::PageUp]) {
            let back = shift || is_key_pressed(KeyCode::PageUp);
            self.next_scene(if back { -1 } else { 1 });
        }
        // On the web, R on a scene the page handed over is the page's: it
        // reads the scene again from where it came (its address or file).
        let page_reloads = cfg!(target_arch = "wasm32") && matches!(self.source, Source::Upload(_));
        if pressed(&[KeyCode::R]) && !page_reloads {
            self.reset();
        }
        if pressed(&[KeyCode::H]) {
            self.panel = !self.panel;
        }
        if pressed(&[KeyCode::C]) {
            self.frame_view();
        }
        if pressed(&[KeyCode::P]) {
            self.toggle_poke();
        }
        if pressed(&[KeyCode::W]) {
            self.look.springs = !self.look.springs;
        }
        if pressed(&[KeyCode::F]) {
            self.look.faces = !self.look.faces;
        }
        let zoom = [KeyCode::Equal, KeyCode::KpAdd, KeyCode::Z];
        let unzoom = [KeyCode::Minus, KeyCode::KpSubtract, KeyCode::X];
        let step = 8.0;
        let moves = [
            (pressed(&zoom) as i32 as f32, Vec2::ZERO),
            (-(pressed(&unzoom) as i32 as f32), Vec2::ZERO),
            (
                0.0,
                vec2(-step, 0.0) * is_key_down(KeyCode::Left) as i32 as f32,
            ),
            (
                0.0,
                vec2(step, 0.0) * is_key_down(KeyCode::Right) as i32 as f32,
            ),
            (
                0.0,
                vec2(0.0, -step) * is_key_down(KeyCode::Up) as i32 as f32,
            ),
            (
                0.0,
                vec2(0.0, step) * is_key_down(KeyCode::Down) as i32 as f32,
            ),
        ];
        for (zoom, drag) in moves {
            if zoom != 0.0 || drag != Vec2::ZERO {
                self.view.zoom(zoom);
                self.view.drag(drag);
                self.auto_fit = false;
            }
        }
        let Some(sim) = self.sim.as_mut() else {
            return;
        };
        if pressed(&[KeyCode::Space]) {
            sim.paused = !sim.paused;
        }
        if pressed(&[KeyCode::S, KeyCode::N]) {
            sim.paused = true;
            if sim.failure.is_none() {
                sim.step_once();
            }
        }
        if pressed(&[KeyCode::I]) {
            cycle_integrator(sim, if shift { -1 } else { 1 });
        }
        if pressed(&[KeyCode::LeftBracket]) {
            scale_dt(sim, 0.5);
        }
        if pressed(&[KeyCode::RightBracket]) {
            scale_dt(sim, 2.0);
        }
    }

    /// The mouse over the world: grab, drag and let go; orbit or pan; zoom.
    pub(crate) fn mouse(&mut self, viewport: Rect, over_ui: bool) {
        let cursor: Vec2 = mouse_position().into();
        let moved = cursor - self.last_mouse;
        self.last_mouse = cursor;
        let shift = is_key_down(KeyCode::LeftShift) || is_key_down(KeyCode::RightShift);
        if !over_ui {
            let right = is_mouse_button_down(MouseButton::Right);
            let middle = is_mouse_button_down(MouseButton::Middle);
            if (right || middle) && moved != Vec2::ZERO {
                if middle || shift {
                    self.view.pan(moved, viewport);
                } else {
                    self.view.drag(moved);
                }
                self.auto_fit = false;
            }
            let wheel = mouse_wheel().1;
            if wheel != 0.0 {
                self.view.zoom(wheel.signum());
                self.auto_fit = false;
            }
        }
        let through = match self.view {
            View::Orbit(orbit) => orbit.target,
            View::Flat(_) => Vec3::ZERO,
        };
        if !over_ui {
            self.cursor_world = self.view.cursor_point(cursor, through, viewport);
        }
        let Some(sim) = self.sim.as_mut() else {
            return;
        };
        let world = &mut sim.world;
        let dt = sim.settings.dt;
        let free = !over_ui && self.hand.poke.is_none() && self.hand.grab.is_none();
        self.hover = free
            .then(|| pick(world, &self.view, viewport, cursor))
            .flatten();
        if is_mouse_button_pressed(MouseButton::Left) {
            if let Some(particle) = self.hover {
                self.hand.grab(world, particle, dt);
            }
        }
        if is_mouse_button_down(MouseButton::Left) {
            self.hand.drag(world, &self.view, viewport, cursor, dt);
            if let Some(grab) = self.hand.grab {
                self.cursor_world = grab.target;
            }
        } else if self.hand.grab.is_some() {
            self.hand.release(world);
        }
    }
}
