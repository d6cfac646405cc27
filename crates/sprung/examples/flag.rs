//! A flag in the wind, written out as frames a viewer plays.
//!
//! Shows: a cloth pinned along one edge, the `Wind` force, and the exports
//! of `sprung-io` as `sprung run` writes them: `diagnostics.csv` (a row per
//! frame, with a probed particle), VTK XML frames and their `frames.pvd`
//! series, which ParaView opens.
//!
//!     cargo run --release -p sprung --example flag [-- OUT_DIR]
//!
//! OUT_DIR defaults to `out/examples/flag`.

use std::path::PathBuf;

use sprung::forces::{WindField, WindModel};
use sprung::prelude::*;
use sprung_io::export::{self, Diagnostics, FrameFormat};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args_os()
        .nth(1)
        .map_or_else(|| PathBuf::from("out/examples/flag"), PathBuf::from);

    // 15 × 10 particles over 1.5 m × 1 m, the x = 0 column pinned (the
    // pole), turned 10° about y so the wind along +x catches it.
    let (nx, ny) = (15, 10);
    let pole = (0..ny).map(|y| y * nx).collect();
    let flag = build::cloth(nx, ny, 1.5, 1.0, ClothSprings::default())?
        .with_total_mass(0.3)
        .with_stiffness(400.0)
        .with_damping(0.02)
        .with_pinned(pole)
        .placed(1.0, Vec3::new(0.0, 10.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("flag", flag)?;
    let field = WindField::uniform(Vec3::new(8.0, 0.0, 0.0));
    world
        .forces
        .set(Wind::new(field, WindModel::Simple { coefficient: 0.02 })?);

    // The free top corner is probed: its x, y, z are columns of the table.
    let corner = ny * nx - 1;
    let frames = out.join("frames");
    std::fs::create_dir_all(&frames)?;
    let mut diagnostics = Diagnostics::create(&out.join("diagnostics.csv"), &world, &[corner])?;

    // Half the stable step; a frame every 0.05 s for 2 s.
    let dt = 0.5 * world.stable_time_step();
    let steps_per_frame = (0.05 / dt).ceil() as usize;
    let format = FrameFormat::Vtu;
    for frame in 0..=40 {
        if frame > 0 {
            for _ in 0..steps_per_frame {
                world.step(dt)?;
            }
        }
        diagnostics.record(&world)?;
        export::write_frame(&frames, frame, &world, format)?;
    }
    export::write_series(&frames, format, &world, diagnostics.times())?;
    let rows = diagnostics.rows();
    diagnostics.finish()?;

    let x = world.particles.position[corner];
    println!(
        "{} steps of {dt:.2e} s, {:.2} s simulated",
        world.steps(),
        world.time()
    );
    println!("free corner at ({:.3}, {:.3}, {:.3}) m", x.x, x.y, x.z);
    println!("{rows} rows: {}", out.join("diagnostics.csv").display());
    println!("{rows} frames: {}", frames.join("frame_*.vtu").display());
    if let Some(series) = export::series_path(&frames, format) {
        println!("open in ParaView: {}", series.display());
    }
    // The wind has blown the flag out along +x, the pole holding it.
    assert!(x.x > 1.0, "the free corner is at x = {} m", x.x);
    Ok(())
}
