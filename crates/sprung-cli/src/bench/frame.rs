//! Issue 51's figures of `projective`'s substitution, after the table of
//! `sprung bench --only frame`: for each light cloth, the factor of
//! `M + dt² L` at the frame step, what one substitution reads of it and
//! computes, its time on one thread and on all, and the share of the
//! STREAM triad's bandwidth that reading reaches (docs/performance.md,
//! "The substitutions").

use sprung::integrate::{measure_substitution, Preconditioner};
use sprung::{parallel, IntegratorKind};

use super::stiff_cloth::{light_cloth, FRAME};
use crate::error::CliError;

/// Time the substitution of each light cloth of `sizes` on `pools` and
/// print a line each; `stream` is the STREAM triad on those pools (B/s),
/// where it was measured; each timing fills `seconds` (s).
pub fn print_substitutions(
    sizes: &[usize],
    pools: [&parallel::Pool; 2],
    stream: Option<[f64; 2]>,
    seconds: f64,
) -> Result<(), CliError> {
    println!(
        "\nprojective's substitution (forwards and back, x, y and z), the light cloths at dt = 1/60 s:"
    );
    println!(
        "{:<12} {:>12} {:>14} {:>16} {:>3} {:>10} {:>8} {:>8}",
        "cloth", "values", "MB read", "multiply-adds", "thr", "ms", "GB/s", "STREAM"
    );
    for &size in sizes {
        let world = light_cloth(size, IntegratorKind::Projective, Preconditioner::Auto)?;
        let model = world.model();
        for (k, pool) in pools.iter().enumerate() {
            let figures = pool
                .install(|| measure_substitution(&model, FRAME, seconds))
                .map_err(|e| CliError::Input(format!("bench, substitution {size}²: {e}")))?;
            let rate = figures.bytes / figures.seconds;
            let share = stream.map_or_else(|| "–".into(), |s| format!("{:.2}", rate / s[k]));
            println!(
                "{:<12} {:>12} {:>14.2} {:>16.3e} {:>3} {:>10.3} {:>8.1} {:>8}",
                format!("{size}²"),
                figures.values,
                figures.bytes / 1e6,
                figures.multiply_adds,
                pool.threads(),
                figures.seconds * 1e3,
                rate / 1e9,
                share
            );
        }
    }
    Ok(())
}
