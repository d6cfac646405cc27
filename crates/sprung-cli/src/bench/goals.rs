//! `sprung bench --goals`: the goals of the speed issue (35) in one run,
//! each figure measured now beside the figure before it and the goal's
//! target. "Before" is the previous turn's: measured again in this run
//! where the old way can still be chosen (`implicit_euler`'s Jacobi
//! preconditioner, its default until this turn), else as the issue
//! recorded it on the project's 2-core AMD EPYC VM (to compare only on
//! that machine), and MuJoCo's figures, the peer the issue names, as the
//! issue measured them there. docs/performance.md, "Goals", holds a run.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use rayon::prelude::*;
use sprung::integrate::Preconditioner;
use sprung::{parallel, IntegratorKind, Real};
use sprung_io::export::AtomicFile;

use super::cases::{self, Case, Group, Step};
use super::stiff_cloth::{light_cloth, FRAME};
use super::{reference, time};
use crate::error::CliError;

/// What a figure was before this turn.
#[derive(Debug, Clone, PartialEq)]
enum Before {
    /// Measured in this run, the old way (what it was).
    Now(f64, &'static str),
    /// As the issue recorded it (where).
    Recorded(f64, &'static str),
    /// Not recorded.
    Unknown,
}

/// A goal's bound on its figure.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Target {
    AtMost(f64),
    AtLeast(f64),
}

impl Target {
    fn met(self, value: f64) -> bool {
        match self {
            Target::AtMost(bound) => value <= bound,
            Target::AtLeast(bound) => value >= bound,
        }
    }
}

/// One line of the table.
#[derive(Debug, Clone)]
struct Line {
    goal: u8,
    what: String,
    threads: usize,
    now: f64,
    unit: &'static str,
    before: Before,
    target: Target,
    /// The lowest and highest of the rounds, for a paired ratio
    /// ([`paired_ratio`]).
    spread: Option<(f64, f64)>,
}

impl Line {
    /// Whether the goal is met: the figure within its bound; a paired
    /// ratio is over its bound only when every round is (one round at or
    /// under it: equal within what the machine's noise lets one tell).
    fn met(&self) -> bool {
        match (self.target, self.spread) {
            (Target::AtMost(bound), Some((lowest, _))) => lowest <= bound,
            (target, _) => target.met(self.now),
        }
    }
}

/// The frame step's time: a step at most this long runs in real time (ms).
const FRAME_MS: f64 = 1e3 * FRAME;

/// MuJoCo 4.0's flex cloth (implicit `discrete` integrator), the same
/// light cloth at the frame step on one thread, as issue 35 measured it
/// (ms a step): 10.8, 1.48 and 0.23 times real time.
const MUJOCO_MS: [(usize, f64); 3] = [(32, 1.54), (64, 11.3), (128, 72.5)];

/// Where the recorded figures come from.
const ISSUE: &str = "issue 35, EPYC VM";

/// Steps timed of a light cloth under the implicit solvers (half a
/// simulated second at the frame step, the cloth swinging down).
const STIFF_STEPS: u32 = 30;

/// Worlds stepped at once for goal 3, and the scene each is.
const WORLDS: usize = 8;
const WORLD_DEMO: &str = "ball3d";

/// Time issue 35's goals and print them (and write them to `csv`).
pub fn run(
    one_pool: &parallel::Pool,
    all_pool: &parallel::Pool,
    quick: bool,
    csv: Option<&Path>,
) -> Result<(), CliError> {
    let all = all_pool.threads();
    let (steps, seconds) = (if quick { 2 } else { STIFF_STEPS }, 0.0);
    let light = |size: usize, kind, pc| Case {
        group: Group::Stiff,
        name: format!("light stiff cloth {size}²"),
        integrator: kind,
        build: Box::new(move || light_cloth(size, kind, pc)),
        dt: Step::Fixed(FRAME),
        compare: false,
        least_steps: 0,
    };
    let ms = |case: &Case, pool: &parallel::Pool| -> Result<f64, CliError> {
        Ok(1e3 * time(case, pool, steps, seconds)?.seconds_per_step)
    };
    let (implicit, projective) = (IntegratorKind::ImplicitEuler, IntegratorKind::Projective);
    let (auto, jacobi) = (Preconditioner::Auto, Preconditioner::Jacobi);
    // The threads' ratios first: a stiff world stepped on two threads
    // leaves them slower for a while after (docs/performance.md, "Goals").
    let mut lines = Vec::new();
    let mut push = |line: Line| lines.push(line);
    eprintln!("timing goals 2 to 4, then 1 (about two and a half minutes)");
    let (slowest, ratio, spread) = slowest_explicit(one_pool, all_pool, quick)?;
    push(Line {
        goal: 2,
        what: format!("slowest explicit cloth: {slowest}, time / 1 thread's"),
        threads: all,
        now: ratio,
        unit: "",
        before: Before::Unknown,
        target: Target::AtMost(1.0),
        spread: Some(spread),
    });
    // Goal 3: many worlds at once.
    // As many steps as take a second on one thread, then the same steps,
    // from the same start, on all of them.
    let least = if quick { 0.0 } else { 1.0 };
    let mut world_steps = 200;
    let mut one = worlds_seconds(one_pool, world_steps)?;
    while one < least && world_steps < 1 << 20 {
        world_steps *= 2;
        one = worlds_seconds(one_pool, world_steps)?;
    }
    push(Line {
        goal: 3,
        what: format!("{WORLDS} {WORLD_DEMO} worlds at once, speed-up"),
        threads: all,
        now: one / worlds_seconds(all_pool, world_steps)?,
        unit: "×",
        before: Before::Unknown,
        target: Target::AtLeast(1.8),
        spread: None,
    });
    // Goal 4: the kernel on the 256² cloth.
    let size = if quick { 16 } else { 256 };
    let case = Case {
        group: Group::Cloth,
        name: format!("cloth {size}²"),
        integrator: IntegratorKind::SymplecticEuler,
        build: Box::new(move || cases::cloth(size, IntegratorKind::SymplecticEuler)),
        dt: Step::HalfStable,
        compare: true,
        least_steps: 0,
    };
    let (kernel_steps, kernel_seconds) = if quick { (2, 0.0) } else { (50, 0.5) };
    let row = time(&case, all_pool, kernel_steps, kernel_seconds)?;
    let world = (case.build)()?;
    let dt = cases::step_of(&case, &world);
    let textbook = reference::seconds_per_step(&world, dt, kernel_steps, kernel_seconds);
    push(Line {
        goal: 4,
        what: format!("cloth {size}², symplectic Euler, spring updates"),
        threads: all,
        now: row.spring_updates().unwrap_or(0.0),
        unit: "/s",
        before: Before::Recorded(9.2e8, ISSUE),
        target: Target::AtLeast(2e9),
        spread: None,
    });
    push(Line {
        goal: 4,
        what: format!("cloth {size}², symplectic Euler, × the textbook loop"),
        threads: all,
        now: textbook / row.seconds_per_step,
        unit: "×",
        before: Before::Recorded(4.8, ISSUE),
        target: Target::AtLeast(10.0),
        spread: None,
    });
    // Goal 2: a few thousand particles gain from the second thread, and
    // nothing loses.
    let mid = if quick { 8 } else { 64 };
    let case = light(mid, implicit, auto);
    let (ratio, spread) = paired_ratio(&case, one_pool, all_pool, steps, seconds, quick)?;
    push(Line {
        goal: 2,
        what: format!("light stiff cloth {mid}², implicit_euler, time / 1 thread's"),
        threads: all,
        now: ratio,
        unit: "",
        before: Before::Recorded(1.0, ISSUE),
        target: Target::AtMost(1.0),
        spread: Some(spread),
    });
    // Goal 1: the 128² light cloth at the frame rate on every thread.
    let big = if quick { 16 } else { 128 };
    push(Line {
        goal: 1,
        what: format!("light stiff cloth {big}², implicit_euler"),
        threads: all,
        now: ms(&light(big, implicit, auto), all_pool)?,
        unit: "ms/step",
        before: Before::Now(ms(&light(big, implicit, jacobi), all_pool)?, "Jacobi pc."),
        target: Target::AtMost(FRAME_MS),
        spread: None,
    });
    push(Line {
        goal: 1,
        what: format!("light stiff cloth {big}², projective"),
        threads: all,
        now: ms(&light(big, projective, auto), all_pool)?,
        unit: "ms/step",
        before: Before::Recorded(19.0, ISSUE),
        target: Target::AtMost(FRAME_MS),
        spread: None,
    });
    // ... ahead of MuJoCo on one thread at every size.
    for (size, mujoco) in MUJOCO_MS {
        let size = if quick { size / 8 } else { size };
        for kind in [implicit, projective] {
            let before = if kind == implicit {
                Before::Now(ms(&light(size, kind, jacobi), one_pool)?, "Jacobi pc.")
            } else {
                Before::Unknown
            };
            push(Line {
                goal: 1,
                what: format!("light stiff cloth {size}², {}, vs MuJoCo", kind.name()),
                threads: 1,
                now: ms(&light(size, kind, auto), one_pool)?,
                unit: "ms/step",
                before,
                target: Target::AtMost(mujoco),
                spread: None,
            });
        }
    }
    // ... and the 256² one within 4 times real time.
    let huge = if quick { 16 } else { 256 };
    push(Line {
        goal: 1,
        what: format!("light stiff cloth {huge}², projective"),
        threads: all,
        now: ms(&light(huge, projective, auto), all_pool)?,
        unit: "ms/step",
        before: Before::Recorded(FRAME_MS / 0.11, ISSUE),
        target: Target::AtMost(4.0 * FRAME_MS),
        spread: None,
    });
    lines.sort_by_key(|line| line.goal);
    for (k, line) in lines.iter().enumerate() {
        print_line(line, k == 0);
    }
    let met = lines.iter().filter(|l| l.met()).count();
    println!("goals met: {met} of {}", lines.len());
    if let Some(path) = csv {
        AtomicFile::write(path, table(&lines).as_bytes())
            .map_err(|e| CliError::Io(format!("cannot write {}: {e}", path.display())))?;
        println!("table written to {}", path.display());
    }
    Ok(())
}

/// The explicit cloth (and integrator) whose time on every thread is most
/// surely the largest share of its time on one (the highest lowest round
/// of [`paired_ratio`]), with that share and its spread: the cloths of
/// `cases::cloth` from 4² to 1024² (16 to 1 048 576 particles) under
/// symplectic Euler, and 48² to 96²
/// (where the springs are cut finer) under RK4 and Verlet too.
fn slowest_explicit(
    one_pool: &parallel::Pool,
    all_pool: &parallel::Pool,
    quick: bool,
) -> Result<(String, f64, (f64, f64)), CliError> {
    let (steps, seconds) = if quick { (2, 0.0) } else { (20, 0.6) };
    let mut tried = Vec::new();
    let sizes: &[usize] = if quick {
        &[8]
    } else {
        &[4, 16, 32, 48, 64, 96, 128, 256, 512, 1024]
    };
    for &size in sizes {
        tried.push((size, IntegratorKind::SymplecticEuler));
        if (48..=96).contains(&size) || quick {
            tried.push((size, IntegratorKind::Rk4));
            tried.push((size, IntegratorKind::Verlet));
        }
    }
    let mut slowest = (String::new(), 0.0, (0.0, 0.0));
    for (size, kind) in tried {
        let case = Case {
            group: Group::Cloth,
            name: format!("{size}² {}", kind.name()),
            integrator: kind,
            build: Box::new(move || cases::cloth(size, kind)),
            dt: Step::HalfStable,
            compare: false,
            least_steps: 0,
        };
        let (ratio, spread) = paired_ratio(&case, one_pool, all_pool, steps, seconds, quick)?;
        if spread.0 > slowest.2 .0 {
            slowest = (case.name, ratio, spread);
        }
    }
    Ok(slowest)
}

/// Rounds of [`paired_ratio`]: a ratio of two timings on this noisy VM
/// moves by some 10 % from one to the next, and the slowest of many
/// such ratios would pick the noise.
const ROUNDS: usize = 5;

/// `case`'s time a step on `all_pool` over its time on `one_pool`: the
/// median of [`ROUNDS`] ratios, each of the two timed one after the
/// other (a share of `seconds` each), so that the machine's drift falls
/// on both alike; with the lowest and highest ratio.
fn paired_ratio(
    case: &Case,
    one_pool: &parallel::Pool,
    all_pool: &parallel::Pool,
    steps: u32,
    seconds: f64,
    quick: bool,
) -> Result<(f64, (f64, f64)), CliError> {
    let rounds = if quick { 1 } else { ROUNDS };
    let share = seconds / rounds as f64;
    let mut ratios = Vec::with_capacity(rounds);
    for _ in 0..rounds {
        let one = time(case, one_pool, steps, share)?.seconds_per_step;
        ratios.push(time(case, all_pool, steps, share)?.seconds_per_step / one);
    }
    ratios.sort_by(f64::total_cmp);
    Ok((ratios[rounds / 2], (ratios[0], ratios[rounds - 1])))
}

/// Wall-clock seconds for [`WORLDS`] fresh copies of the demo
/// [`WORLD_DEMO`] to take `steps` steps each on `pool`, one world a task
/// (as a Python `Batch` and a local sweep share worlds among threads).
fn worlds_seconds(pool: &parallel::Pool, steps: u32) -> Result<f64, CliError> {
    let demo = sprung_io::demos::find(WORLD_DEMO)
        .ok_or_else(|| CliError::Input(format!("no demo {WORLD_DEMO}")))?;
    let mut worlds = Vec::with_capacity(WORLDS);
    let mut dt: Real = 0.0;
    for _ in 0..WORLDS {
        let scene = demo.load()?;
        dt = scene.dt;
        worlds.push(scene.world);
    }
    let start = Instant::now();
    pool.install(|| {
        worlds
            .par_iter_mut()
            .try_for_each(|world| (0..steps).try_for_each(|_| world.step(dt).map(|_| ())))
    })
    .map_err(|e| CliError::Input(format!("bench, {WORLD_DEMO}: {e}")))?;
    Ok(start.elapsed().as_secs_f64())
}

/// `value` with its unit, in the table's style.
fn figure(value: f64, unit: &str) -> String {
    match unit {
        "/s" => format!("{value:.3e}/s"),
        "×" => format!("{value:.2}×"),
        "" => format!("{value:.2}"),
        unit => format!("{value:.2} {unit}"),
    }
}

fn print_line(line: &Line, header: bool) {
    if header {
        println!(
            "{:<4} {:<60} {:>3} {:>16} {:>34} {:>12} {:>7}",
            "goal", "figure", "thr", "this run", "before", "target", "met"
        );
    }
    let before = match &line.before {
        Before::Now(v, how) => format!("{} ({how}, now)", figure(*v, line.unit)),
        Before::Recorded(v, whence) => format!("{} ({whence})", figure(*v, line.unit)),
        Before::Unknown => "–".into(),
    };
    let target = match line.target {
        Target::AtMost(b) => format!("≤ {}", figure(b, line.unit)),
        Target::AtLeast(b) => format!("≥ {}", figure(b, line.unit)),
    };
    let now = match line.spread {
        Some((lowest, highest)) => format!(
            "{} ({}–{})",
            figure(line.now, line.unit),
            figure(lowest, line.unit),
            figure(highest, line.unit)
        ),
        None => figure(line.now, line.unit),
    };
    println!(
        "{:<4} {:<60} {:>3} {:>16} {:>34} {:>12} {:>7}",
        line.goal,
        line.what,
        line.threads,
        now,
        before,
        target,
        if line.met() { "yes" } else { "no" }
    );
}

/// The goals as CSV, one line each.
fn table(lines: &[Line]) -> String {
    let mut text = String::from(
        "goal,figure,threads,now,lowest,highest,unit,before,before_from,target,bound,met\n",
    );
    for line in lines {
        let (before, from) = match &line.before {
            Before::Now(v, how) => (format!("{v:e}"), format!("this run, {how}")),
            Before::Recorded(v, whence) => (format!("{v:e}"), (*whence).to_string()),
            Before::Unknown => (String::new(), String::new()),
        };
        let (bound, target) = match line.target {
            Target::AtMost(b) => ("at_most", b),
            Target::AtLeast(b) => ("at_least", b),
        };
        let (lowest, highest) = line
            .spread
            .map_or((String::new(), String::new()), |(l, h)| {
                (format!("{l:e}"), format!("{h:e}"))
            });
        let _ = writeln!(
            text,
            "{},{},{},{:e},{},{},{},{},{},{:e},{},{}",
            line.goal,
            line.what.replace(',', ";"),
            line.threads,
            line.now,
            lowest,
            highest,
            line.unit,
            before,
            from.replace(',', ";"),
            target,
            bound,
            line.met()
        );
    }
    text
}
