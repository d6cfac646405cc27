//! A few immediate-mode controls drawn with macroquad's shapes and text:
//! text lines, buttons, steppers (`< value >`) and sliders, laid out top to
//! bottom in a panel. A button reacts to a press of the left button on
//! it, a slider while it is dragged.

use macroquad::color::Color;
use macroquad::input::{
    is_mouse_button_down, is_mouse_button_pressed, mouse_position, MouseButton,
};
use macroquad::math::{vec2, Rect, Vec2};
use macroquad::shapes::{draw_rectangle, draw_rectangle_lines};

use crate::palette;
use crate::render::{self, FONT};

const PAD: f32 = 14.0;
const ROW: f32 = 28.0;

/// The panel's layout and mouse state for one frame.
#[derive(Debug, Default)]
pub struct Ui {
    area: Rect,
    y: f32,
    mouse: Vec2,
    pressed: bool,
    down: bool,
    /// The slider being dragged (its label), across frames.
    active: Option<String>,
}

impl Ui {
    /// Start laying out controls in `area` with this frame's mouse.
    pub fn begin(&mut self, area: Rect) {
        self.area = area;
        self.y = area.y + PAD;
        self.mouse = mouse_position().into();
        self.pressed = is_mouse_button_pressed(MouseButton::Left);
        self.down = is_mouse_button_down(MouseButton::Left);
        if !self.down {
            self.active = None;
        }
        draw_rectangle(area.x, area.y, area.w, area.h, palette::PANEL);
    }

    /// The mouse is over the panel or dragging one of its sliders.
    pub fn wants_mouse(&self, area: Rect) -> bool {
        area.contains(mouse_position().into()) || self.active.is_some()
    }

    fn width(&self) -> f32 {
        self.area.w - 2.0 * PAD
    }

    /// A line of text in `colour` (`size` pixels).
    pub fn text(&mut self, text: &str, size: f32, colour: Color) {
        self.y += size;
        render::text(text, self.area.x + PAD, self.y, size, colour);
        self.y += 0.35 * size;
    }

    /// Text in two columns: a name on the left, a value on the right.
    pub fn pair(&mut self, name: &str, value: &str, colour: Color) {
        let size = FONT - 2.0;
        self.y += size;
        render::text(name, self.area.x + PAD, self.y, size, palette::DIM);
        let width = render::text_width(value, size);
        render::text(value, self.area.right() - PAD - width, self.y, size, colour);
        self.y += 0.3 * size;
    }

    /// Vertical space.
    pub fn gap(&mut self, pixels: f32) {
        self.y += pixels;
    }

    /// A thin line across the panel.
    pub fn rule(&mut self) {
        self.y += 6.0;
        draw_rectangle(self.area.x + PAD, self.y, self.width(), 1.0, palette::GRID);
        self.y += 8.0;
    }

    /// Where the next control goes (for drawing beside the panel's flow).
    pub fn cursor(&self) -> Vec2 {
        vec2(self.area.x + PAD, self.y)
    }

    /// A row of buttons sharing the width; `on[i]` draws button `i` lit.
    /// Returns the one clicked.
    pub fn buttons(&mut self, labels: &[&str], on: &[bool]) -> Option<usize> {
        let gap = 6.0;
        let count = labels.len().max(1) as f32;
        let w = (self.width() - gap * (count - 1.0)) / count;
        let mut clicked = None;
        for (i, label) in labels.iter().enumerate() {
            let rect = Rect::new(self.area.x + PAD + i as f32 * (w + gap), self.y, w, ROW);
            let lit = on.get(i).copied().unwrap_or(false);
            if self.button_at(rect, label, lit) {
                clicked = Some(i);
            }
        }
        self.y += ROW + 6.0;
        clicked
    }

    /// `< value >` with a label: -1 or +1 when an arrow is clicked, 0 else.
    pub fn stepper(&mut self, label: &str, value: &str) -> i32 {
        let label_w = 78.0;
        let x = self.area.x + PAD;
        render::text(label, x, self.y + 19.0, FONT - 2.0, palette::DIM);
        let arrow = 26.0;
        let left = Rect::new(x + label_w, self.y, arrow, ROW);
        let right = Rect::new(self.area.right() - PAD - arrow, self.y, arrow, ROW);
        let middle = Rect::new(
            left.right() + 4.0,
            self.y,
            right.x - left.right() - 8.0,
            ROW,
        );
        draw_rectangle(middle.x, middle.y, middle.w, middle.h, palette::CONTROL);
        centred(value, middle, palette::TEXT);
        let step = if self.button_at(left, "<", false) {
            -1
        } else if self.button_at(right, ">", false) {
            1
        } else {
            0
        };
        self.y += ROW + 6.0;
        step
    }

    /// A slider over `t` in [0, 1] with a label and the value as text;
    /// true when dragged this frame.
    pub fn slider(&mut self, label: &str, value: &str, t: &mut f32, enabled: bool) -> bool {
        let size = FONT - 2.0;
        let x = self.area.x + PAD;
        let colour = if enabled { palette::DIM } else { palette::GRID };
        render::text(label, x, self.y + size, size, colour);
        let width = render::text_width(value, size);
        let value_colour = if enabled {
            palette::TEXT
        } else {
            palette::GRID
        };
        render::text(
            value,
            self.area.right() - PAD - width,
            self.y + size,
            size,
            value_colour,
        );
        self.y += size + 8.0;
        let bar = Rect::new(x, self.y, self.width(), 10.0);
        let grab = Rect::new(bar.x - 6.0, bar.y - 8.0, bar.w + 12.0, bar.h + 16.0);
        if enabled && self.pressed && grab.contains(self.mouse) {
            self.active = Some(label.to_string());
        }
        let dragging = enabled && self.down && self.active.as_deref() == Some(label);
        if dragging {
            *t = ((self.mouse.x - bar.x) / bar.w).clamp(0.0, 1.0);
        }
        draw_rectangle(bar.x, bar.y, bar.w, bar.h, palette::CONTROL);
        let fill = if enabled {
            palette::ACCENT
        } else {
            palette::GRID
        };
        draw_rectangle(bar.x, bar.y, bar.w * *t, bar.h, fill);
        let knob = bar.x + bar.w * *t;
        draw_rectangle(knob - 3.0, bar.y - 4.0, 6.0, bar.h + 8.0, value_colour);
        self.y += bar.h + 12.0;
        dragging
    }

    fn button_at(&mut self, rect: Rect, label: &str, lit: bool) -> bool {
        let hot = rect.contains(self.mouse) && self.active.is_none();
        let colour = match (lit, hot) {
            (true, _) => palette::ACCENT,
            (false, true) => palette::CONTROL_HOT,
            (false, false) => palette::CONTROL,
        };
        draw_rectangle(rect.x, rect.y, rect.w, rect.h, colour);
        if hot {
            draw_rectangle_lines(rect.x, rect.y, rect.w, rect.h, 1.0, palette::GRID);
        }
        centred(label, rect, palette::TEXT);
        hot && self.pressed
    }
}

fn centred(text: &str, rect: Rect, colour: Color) {
    let size = FONT - 2.0;
    let width = render::text_width(text, size);
    let x = rect.x + 0.5 * (rect.w - width);
    render::text(text, x, rect.y + 0.5 * rect.h + 0.33 * size, size, colour);
}
