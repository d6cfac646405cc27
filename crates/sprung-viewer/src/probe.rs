//! The viewer's state for tests and for the web page: a copy written at the
//! end of every frame, read through `extern "C"` functions that the wasm
//! module exports (macroquad's `gl.js` keeps them in `wasm_exports`), and a
//! request box the page uses to pick a demo or to open a scene of its own.
//!
//! The page hands a file over through a staging buffer: it asks
//! [`sprung_staging`] for room, writes the file's name then its bytes
//! there, and calls [`sprung_stage_file`] (a mesh) or
//! [`sprung_open_staged_scene`] (the scene, which takes the files staged
//! before it).
//!
//! Screen positions are in the viewer's pixels (CSS pixels of the canvas on
//! the web); world positions in metres.

use std::sync::{Mutex, MutexGuard};

use sprung_io::demos::DEMOS;
use sprung_io::Device;

use crate::demos::Upload;

/// What a frame leaves behind for the page.
#[derive(Debug, Default)]
pub struct Probe {
    /// Frames drawn.
    pub frames: u32,
    /// Frames per second, smoothed.
    pub fps: f32,
    /// Simulated time (s).
    pub time: f64,
    /// Every particle's position (m).
    pub positions: Vec<[f64; 3]>,
    /// Every particle's place on the screen (pixels; NaN if behind the camera).
    pub screen: Vec<[f32; 2]>,
    /// The grabbed particle, if any.
    pub grabbed: Option<usize>,
    /// The cursor's point in the world (m): the grabbed particle's target.
    pub cursor: [f64; 3],
    /// An error is on the screen (a scene that did not load, a blow-up).
    pub error: bool,
    /// The demo shown, if the scene is a demo.
    pub demo: Option<usize>,
    /// A demo the page asked for, taken by the next frame.
    pub request: Option<usize>,
    /// A scene the page handed over, taken by the next frame, and whether
    /// it is the one shown read again (keeping the settings, as a reset).
    pub scene_request: Option<(Upload, bool)>,
    /// The error on the screen, as text (empty when there is none).
    pub message: String,
    /// Where the page asked the steps to run (`?device=`), taken by the
    /// next frame.
    pub device_request: Option<Device>,
    /// Steps taken on the GPU and read back since the scene opened.
    pub gpu_steps: f64,
}

/// The page's staging buffer, and the files staged for the next scene.
struct Staging {
    buffer: Vec<u8>,
    files: Vec<(String, Vec<u8>)>,
}

static STAGING: Mutex<Staging> = Mutex::new(Staging {
    buffer: Vec::new(),
    files: Vec::new(),
});

fn staging() -> MutexGuard<'static, Staging> {
    STAGING
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

static PROBE: Mutex<Probe> = Mutex::new(Probe {
    frames: 0,
    fps: 0.0,
    time: 0.0,
    positions: Vec::new(),
    screen: Vec::new(),
    grabbed: None,
    cursor: [0.0; 3],
    error: false,
    demo: None,
    request: None,
    scene_request: None,
    message: String::new(),
    device_request: None,
    gpu_steps: 0.0,
});

/// The shared probe (a poisoned lock is still readable: the data is plain).
pub fn lock() -> MutexGuard<'static, Probe> {
    PROBE
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn axis<T: Copy>(values: Option<&[T]>, a: u32, missing: T) -> T {
    values
        .and_then(|v| v.get(a as usize).copied())
        .unwrap_or(missing)
}

/// Frames drawn so far.
#[no_mangle]
pub extern "C" fn sprung_frames() -> u32 {
    lock().frames
}

/// Frames per second, smoothed over the last second or so.
#[no_mangle]
pub extern "C" fn sprung_fps() -> f32 {
    lock().fps
}

/// Simulated time (s).
#[no_mangle]
pub extern "C" fn sprung_time() -> f64 {
    lock().time
}

/// Number of particles.
#[no_mangle]
pub extern "C" fn sprung_particle_count() -> u32 {
    lock().positions.len() as u32
}

/// Coordinate `a` (0 x, 1 y, 2 z) of particle `i` (m); NaN if out of range.
#[no_mangle]
pub extern "C" fn sprung_particle(i: u32, a: u32) -> f64 {
    let probe = lock();
    axis(probe.positions.get(i as usize).map(|p| &p[..]), a, f64::NAN)
}

/// Screen coordinate `a` (0 x, 1 y; pixels from the top left) of particle
/// `i`; NaN if out of range or behind the camera.
#[no_mangle]
pub extern "C" fn sprung_particle_screen(i: u32, a: u32) -> f32 {
    let probe = lock();
    axis(probe.screen.get(i as usize).map(|p| &p[..]), a, f32::NAN)
}

/// The grabbed particle, or -1.
#[no_mangle]
pub extern "C" fn sprung_grabbed() -> i32 {
    lock().grabbed.map_or(-1, |i| i as i32)
}

/// Coordinate `a` of the cursor's point in the world (m).
#[no_mangle]
pub extern "C" fn sprung_cursor(a: u32) -> f64 {
    let probe = lock();
    axis(Some(&probe.cursor[..]), a, f64::NAN)
}

/// 1 if an error is shown (a scene that could not be loaded, a blow-up).
#[no_mangle]
pub extern "C" fn sprung_error() -> i32 {
    i32::from(lock().error)
}

/// Number of built-in demos.
#[no_mangle]
pub extern "C" fn sprung_demo_count() -> u32 {
    DEMOS.len() as u32
}

/// The demo shown, or -1 (a scene file).
#[no_mangle]
pub extern "C" fn sprung_demo() -> i32 {
    lock().demo.map_or(-1, |i| i as i32)
}

/// Address of demo `i`'s name (UTF-8, [`sprung_demo_name_len`] bytes) in
/// the module's memory; 0 if out of range.
#[no_mangle]
pub extern "C" fn sprung_demo_name_ptr(i: u32) -> usize {
    DEMOS
        .get(i as usize)
        .map_or(0, |d| d.name.as_ptr() as usize)
}

/// Length in bytes of demo `i`'s name; 0 if out of range.
#[no_mangle]
pub extern "C" fn sprung_demo_name_len(i: u32) -> u32 {
    DEMOS.get(i as usize).map_or(0, |d| d.name.len() as u32)
}

/// Ask for demo `i` to be shown from the next frame; 1 if it exists.
#[no_mangle]
pub extern "C" fn sprung_select_demo(i: u32) -> i32 {
    if (i as usize) < DEMOS.len() {
        lock().request = Some(i as usize);
        1
    } else {
        0
    }
}

/// Run the steps on the GPU (`gpu` 1: the browser's WebGPU) or the
/// engine (0) from the next frame, the scene shown started again; 1 if
/// `gpu` is 0 or 1.
#[no_mangle]
pub extern "C" fn sprung_set_device(gpu: u32) -> i32 {
    let device = match gpu {
        0 => Device::Cpu,
        1 => Device::Gpu,
        _ => return 0,
    };
    lock().device_request = Some(device);
    1
}

/// Steps the GPU has taken and read back since the scene opened.
#[no_mangle]
pub extern "C" fn sprung_gpu_steps() -> f64 {
    lock().gpu_steps
}

/// Room for `len` bytes in the staging buffer: its address in the module's
/// memory (valid until the next call into the module).
#[no_mangle]
pub extern "C" fn sprung_staging(len: u32) -> *mut u8 {
    let mut staging = staging();
    staging.buffer.clear();
    staging.buffer.resize(len as usize, 0);
    staging.buffer.as_mut_ptr()
}

/// The staging buffer, taken (so its memory goes with the file), as a name
/// of `name_len` bytes and the file after it.
fn staged(buffer: &mut Vec<u8>, name_len: u32) -> Option<(String, Vec<u8>)> {
    let mut bytes = std::mem::take(buffer);
    let cut = (name_len as usize).min(bytes.len());
    let file = bytes.split_off(cut);
    let name = String::from_utf8(bytes).ok()?;
    Some((name, file))
}

/// Keep the staged file (a mesh) for the next scene; 1 if its name is
/// UTF-8.
#[no_mangle]
pub extern "C" fn sprung_stage_file(name_len: u32) -> i32 {
    let mut staging = staging();
    match staged(&mut staging.buffer, name_len) {
        Some(file) => {
            staging.files.push(file);
            1
        }
        None => 0,
    }
}

/// Open the staged file as the scene, with the files staged before it,
/// from the next frame; 1 if it was taken, 0 if its name is not UTF-8.
#[no_mangle]
pub extern "C" fn sprung_open_staged_scene(name_len: u32) -> i32 {
    take_staged_scene(name_len, false)
}

/// As [`sprung_open_staged_scene`], for the scene shown read again from
/// where it came (R on the page): the settings (integrator, time step,
/// speed) are kept, as a reset keeps them.
#[no_mangle]
pub extern "C" fn sprung_reload_staged_scene(name_len: u32) -> i32 {
    take_staged_scene(name_len, true)
}

fn take_staged_scene(name_len: u32, reload: bool) -> i32 {
    let mut staging = staging();
    let files = std::mem::take(&mut staging.files);
    match staged(&mut staging.buffer, name_len) {
        Some((name, text)) => {
            lock().scene_request = Some((Upload { name, text, files }, reload));
            1
        }
        None => 0,
    }
}

/// Address of the error on the screen as UTF-8 text ([`sprung_message_len`]
/// bytes), valid until the next frame.
#[no_mangle]
pub extern "C" fn sprung_message_ptr() -> usize {
    lock().message.as_ptr() as usize
}

/// Length in bytes of the error on the screen; 0 when there is none.
#[no_mangle]
pub extern "C" fn sprung_message_len() -> u32 {
    lock().message.len() as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exports_read_the_probe() {
        {
            let mut probe = lock();
            probe.positions = vec![[1.0, 2.0, 3.0]];
            probe.grabbed = Some(0);
        }
        assert_eq!(sprung_particle(0, 1), 2.0);
        assert!(sprung_particle(5, 0).is_nan());
        assert!(sprung_particle(0, 7).is_nan());
        assert_eq!(sprung_grabbed(), 0);
        assert_eq!(sprung_select_demo(1), 1);
        assert_eq!(sprung_select_demo(999), 0);
        assert_eq!(lock().request.take(), Some(1));
        assert_eq!(sprung_demo_name_len(0), DEMOS[0].name.len() as u32);
    }

    /// What the page does: stage a mesh, then the scene.
    fn stage(name: &str, bytes: &[u8]) -> u32 {
        let total = name.len() + bytes.len();
        let at = sprung_staging(total as u32);
        let room = unsafe { std::slice::from_raw_parts_mut(at, total) };
        room[..name.len()].copy_from_slice(name.as_bytes());
        room[name.len()..].copy_from_slice(bytes);
        name.len() as u32
    }

    #[test]
    fn the_page_hands_over_a_scene_with_its_files() {
        let name = stage("box.asc", b"mesh bytes");
        assert_eq!(sprung_stage_file(name), 1);
        let name = stage("mine.toml", b"[sim]\ndt = 1e-3\n");
        assert_eq!(sprung_open_staged_scene(name), 1);
        let (upload, reload) = lock().scene_request.take().expect("a request");
        assert!(!reload);
        assert_eq!(upload.name, "mine.toml");
        assert_eq!(upload.text, b"[sim]\ndt = 1e-3\n");
        assert_eq!(
            upload.files,
            vec![("box.asc".to_string(), b"mesh bytes".to_vec())]
        );
        // Read again (R on the page): the files staged since, and a reload.
        let name = stage("mine.toml", b"[sim]\ndt = 2e-3\n");
        assert_eq!(sprung_reload_staged_scene(name), 1);
        let (upload, reload) = lock().scene_request.take().expect("a request");
        assert!(reload && upload.files.is_empty());
        assert_eq!(upload.text, b"[sim]\ndt = 2e-3\n");
    }
}
