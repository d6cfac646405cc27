//! `sprung bench --demos`: the real-time factor of every demo's physics
//! (simulated seconds per wall-clock second, nothing written), on all
//! threads.

use std::time::Instant;

use sprung::parallel;
use sprung_io::demos::DEMOS;

use crate::error::CliError;

/// Time every demo for at least `steps` steps and `seconds` of wall clock
/// (or its whole run, if shorter) and print its real-time factor.
pub fn run(steps: u32, seconds: f64) -> Result<(), CliError> {
    println!(
        "{:<16} {:<18} {:>9} {:>9} {:>10} {:>8} {:>10} {:>10}",
        "demo", "integrator", "particles", "springs", "dt (s)", "steps", "ms/step", "real time×"
    );
    for demo in DEMOS {
        let mut scene = demo.load()?;
        let start = Instant::now();
        let mut taken = 0u64;
        while taken < scene.steps
            && (taken < u64::from(steps) || start.elapsed().as_secs_f64() < seconds)
        {
            scene
                .world
                .step(scene.dt)
                .map_err(|e| CliError::Input(format!("bench, demo \"{}\": {e}", demo.name)))?;
            taken += 1;
        }
        let elapsed = start.elapsed().as_secs_f64();
        let simulated = taken as f64 * scene.dt;
        println!(
            "{:<16} {:<18} {:>9} {:>9} {:>10.2e} {:>8} {:>10.4} {:>10.2}",
            demo.name,
            scene.world.integrator().name(),
            scene.world.particles.len(),
            scene.world.springs.len(),
            scene.dt,
            taken,
            elapsed * 1e3 / taken.max(1) as f64,
            simulated / elapsed
        );
    }
    println!("on {} threads", parallel::threads());
    Ok(())
}
