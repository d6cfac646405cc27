//! `sprung bench`: the performance suite. Every case (cloths of growing
//! size, one cloth under every integrator, gas balls, the stiff cloth under
//! the implicit solvers, contact scenes; [`cases`]) is built and timed on
//! one thread and on all of them, in one process; per case the table gives
//! the time per step, spring and particle updates per second, the speed-up
//! of the threads, the simulated seconds per wall-clock second, the peak
//! heap and the bytes a step allocates ([`memory`]). `--compare` times the
//! textbook loop on the cloths ([`mod@reference`]); `--demos` the real-time
//! factor of every demo ([`demos`]); `--goals` the speed issue's goals
//! beside the figures before them ([`goals`]); the header gives the memory bandwidth
//! of a STREAM triad ([`stream`]), the bound of the streaming loops.

mod cases;
mod contacts;
mod demos;
mod frame;
mod goals;
mod gpu;
pub mod memory;
mod reference;
mod stiff_cloth;
mod stream;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use sprung::{parallel, IntegratorKind, Real, Stage};
use sprung_io::export::AtomicFile;
use sprung_io::Device;

use crate::error::CliError;
use cases::{Case, Group};

/// A cloth's particles along a side, for `--size` and `--sizes`: at
/// least 2 (a malformed value is a usage error, status 2).
fn cloth_side(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(n) if n >= 2 => Ok(n),
        Ok(n) => Err(format!("{n}: a cloth needs at least 2 particles a side")),
        Err(e) => Err(format!("{text:?}: {e}")),
    }
}

/// `--seconds`: a finite time, not negative (s).
fn least_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(s) if s.is_finite() && s >= 0.0 => Ok(s),
        Ok(s) => Err(format!("{s}: must be a finite, non-negative time")),
        Err(e) => Err(format!("{text:?}: {e}")),
    }
}

/// Options of `sprung bench`.
#[derive(Debug, Clone, clap::Args)]
pub struct BenchArgs {
    /// Particles along each side of the cloth that every integrator steps.
    #[arg(long, default_value_t = 128, value_parser = cloth_side)]
    size: usize,
    /// Steps timed per case and thread count (at least, and at least 300
    /// for the contact scenes, whose pair search runs every few tens of
    /// steps; a case runs on until --seconds have passed, and stops at 10
    /// s or --seconds, the longer, after its first step: the slow implicit
    /// cases).
    #[arg(long, default_value_t = 50, value_parser = clap::value_parser!(u32).range(1..))]
    steps: u32,
    /// Least wall-clock time per case and thread count (s).
    #[arg(long, default_value_t = 0.5, value_parser = least_seconds)]
    seconds: f64,
    /// Sizes of the cloths timed under symplectic Euler (particles along a
    /// side); the largest is also timed under RK4 [default: 64,128,256,512;
    /// 256,512,1024 with --device gpu].
    #[arg(long, value_delimiter = ',', value_parser = cloth_side)]
    sizes: Vec<usize>,
    /// Only these groups of cases.
    #[arg(long, value_delimiter = ',', value_enum)]
    only: Vec<Group>,
    /// Also write the table to this CSV file.
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Also time a plain single-threaded loop in the textbook's style (an
    /// array of particle structs, an array of springs, f64) on each cloth,
    /// and print sprung's speed as a multiple of it.
    #[arg(long)]
    compare: bool,
    /// Instead, time every demo's physics on all threads: its real-time
    /// factor (simulated seconds per wall-clock second).
    #[arg(long)]
    demos: bool,
    /// Instead, time the goals of the speed issue (35): each figure in
    /// this run beside the previous turn's (the old default measured
    /// again, or the figure the issue recorded) and the goal's target.
    #[arg(long, conflicts_with = "demos")]
    goals: bool,
    /// Where the cloths are stepped: cpu (the table above), gpu or
    /// gpu_f64 (the GPU step in f32 or f64 against the engine on every
    /// thread: --sizes, default 256, 512 and 1024, and the largest under
    /// RK4 too).
    #[arg(long, default_value = "cpu", conflicts_with_all = ["demos", "goals", "compare", "only"])]
    device: Device,
    /// Small cases and short timings: checks that the bench runs, measures
    /// nothing.
    #[arg(long)]
    quick: bool,
}

/// Wall-clock time after which a case stops timing, once it has taken a
/// step, even short of `--steps` (s).
const LONGEST_SECONDS: f64 = 10.0;

/// One timed case on one number of threads.
#[derive(Debug, Clone)]
struct Row {
    group: Group,
    name: String,
    integrator: IntegratorKind,
    particles: usize,
    springs: usize,
    threads: usize,
    dt: Real,
    steps: u32,
    seconds_per_step: f64,
    /// Force evaluations per step, for the spring updates (`None` where
    /// they vary: the implicit solvers and rk45).
    evaluations: Option<u32>,
    /// The most heap in use from the start of building the world to the
    /// end of its steps (bytes).
    peak_bytes: usize,
    /// The most heap in use while it steps: the running world's footprint
    /// (bytes).
    stepping_bytes: usize,
    /// Bytes allocated by the median timed step: zero once a world's
    /// buffers have their size (the contact scenes grow theirs while
    /// contacts form, to a high-water mark). The median, not the mean: the
    /// count is the whole process's, and the thread pool's own bookkeeping
    /// (its job queues grow and shrink with the scheduling) now and then
    /// allocates during one step; a step that allocates every time shows.
    allocated_per_step: usize,
    /// Seconds per step of the same case on one thread.
    one_thread: f64,
    /// Seconds per step of the textbook loop, under `--compare`.
    reference: Option<f64>,
    /// The mean number of candidate contact pairs between bodies over the
    /// timed steps (contact cases only): the contact stage's work.
    contact_pairs: Option<f64>,
    /// The share of the timed steps spent in the CCD's stage
    /// (`ccd`; contact cases only, timed by the world's profile).
    ccd_share: Option<f64>,
    /// The share of the timed steps spent in the give stage (springs that
    /// yield and break; `give` cases only).
    give_share: Option<f64>,
    /// The bytes a step must move over the STREAM triad's rate on as many
    /// threads ([`bytes_per_step`]; symplectic Euler's cloths, where the
    /// triad was measured).
    stream_share: Option<f64>,
}

/// The bytes a symplectic-Euler step must move at the least: each spring's
/// 34 bytes of the schedule, read once (docs/performance.md, "Against the
/// bounds"); each particle's position and velocity (f64 × 3) read and
/// written, its inverse mass read. 20.1 MB for the 256² cloth. `None` for
/// the other integrators, whose passes over the data vary.
fn bytes_per_step(kind: IntegratorKind, particles: usize, springs: usize) -> Option<f64> {
    const SPRING: usize = 34;
    const PARTICLE: usize = 4 * 3 * 8 + 8;
    (kind == IntegratorKind::SymplecticEuler)
        .then(|| (springs * SPRING + particles * PARTICLE) as f64)
}

impl Row {
    fn spring_updates(&self) -> Option<f64> {
        self.evaluations
            .map(|e| f64::from(e) * self.springs as f64 / self.seconds_per_step)
    }

    fn particle_updates(&self) -> f64 {
        self.particles as f64 / self.seconds_per_step
    }
}

/// The median of `values` (0 for none).
fn median(values: &mut [usize]) -> usize {
    values.sort_unstable();
    values.get(values.len() / 2).copied().unwrap_or(0)
}

/// Run the bench (or the demos' real-time factors) and print the table.
pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    if let Some(path) = &args.csv {
        // Refused before the minutes of timing, not after them.
        let folder = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => std::path::Path::new("."),
        };
        let names_a_folder = path.as_os_str().is_empty()
            || path.is_dir()
            || path.to_string_lossy().ends_with(std::path::MAIN_SEPARATOR);
        if names_a_folder || !folder.is_dir() {
            return Err(CliError::Input(format!(
                "--csv {:?}: {}",
                path.display().to_string(),
                if names_a_folder {
                    "names a folder, or nothing; give a file"
                } else {
                    "its folder does not exist"
                }
            )));
        }
    }
    let all = parallel::threads();
    let (steps, seconds) = if args.quick {
        (2, 0.0)
    } else {
        (args.steps, args.seconds)
    };
    let threads_error = |e: parallel::ThreadsError| CliError::Input(e.to_string());
    // One pool per thread count for the whole run: a pool started per case
    // would count its threads' start and exit in the case's measurements.
    let one_pool = parallel::Pool::new(1).map_err(threads_error)?;
    let all_pool = parallel::Pool::new(all).map_err(threads_error)?;
    let (header, stream) = machine(&one_pool, &all_pool, args.quick);
    println!("{header}");
    if args.demos {
        let least = if args.quick { 0.0 } else { seconds.max(1.0) };
        return all_pool.install(|| demos::run(steps, least));
    }
    if args.goals {
        return goals::run(&one_pool, &all_pool, args.quick, args.csv.as_deref());
    }
    if args.device.is_gpu() {
        let (sizes, least) = match (args.quick, args.sizes.is_empty()) {
            (true, _) => (vec![8, 16], 0.0),
            (false, false) => (args.sizes.clone(), seconds),
            (false, true) => (vec![256, 512, 1024], seconds),
        };
        let precision = crate::on_gpu::precision(args.device);
        return gpu::run(&all_pool, &sizes, least, precision, args.csv.as_deref());
    }
    let sizes = match (args.quick, args.sizes.is_empty()) {
        (true, _) => vec![8, 16],
        (false, true) => vec![64, 128, 256, 512],
        (false, false) => args.sizes.clone(),
    };
    let size = if args.quick { 8 } else { args.size };
    let mut rows = Vec::new();
    for case in cases::cases(&args.only, &sizes, size, args.quick) {
        let one = time(&case, &one_pool, steps, seconds)?;
        let one_thread = one.seconds_per_step;
        let reference = (args.compare && case.compare)
            .then(|| {
                let world = (case.build)()?;
                let dt = cases::step_of(&case, &world);
                Ok::<_, CliError>(reference::seconds_per_step(&world, dt, steps, seconds))
            })
            .transpose()?;
        let mut timed = vec![one];
        if all > 1 {
            timed.push(time(&case, &all_pool, steps, seconds)?);
        }
        for mut row in timed {
            row.one_thread = one_thread;
            row.reference = reference;
            let bandwidth = stream.map(|s| s[usize::from(row.threads > 1)]);
            row.stream_share = bytes_per_step(row.integrator, row.particles, row.springs)
                .zip(bandwidth)
                .map(|(bytes, rate)| bytes / row.seconds_per_step / rate);
            print_row(&row, rows.is_empty());
            rows.push(row);
        }
    }
    if args.only.contains(&Group::Frame) {
        let least = if args.quick { 0.0 } else { seconds.max(0.5) };
        frame::print_substitutions(
            cases::frame_sizes(args.quick),
            [&one_pool, &all_pool],
            stream,
            least,
        )?;
    }
    if let Some(path) = &args.csv {
        AtomicFile::write(path, csv(&rows).as_bytes())
            .map_err(|e| CliError::Io(format!("cannot write {}: {e}", path.display())))?;
        println!("table written to {}", path.display());
    }
    Ok(())
}

/// The machine, the threads and the memory bandwidth, for the header; and
/// the STREAM triad on one thread and on all (B/s), unless `quick`.
fn machine(
    one_pool: &parallel::Pool,
    all_pool: &parallel::Pool,
    quick: bool,
) -> (String, Option<[f64; 2]>) {
    let threads = all_pool.threads();
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|name| name.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    let mut header = format!(
        "machine: {cpu}, {threads} thread{} (sprung --threads N or SPRUNG_THREADS to change)",
        if threads == 1 { "" } else { "s" }
    );
    let mut triad = None;
    if !quick {
        let one = stream::triad_bytes_per_second(one_pool);
        let every = stream::triad_bytes_per_second(all_pool);
        triad = Some([one, every]);
        let _ = write!(
            header,
            "\nmemory bandwidth (STREAM triad, 3 × 64 MiB): {:.1} GB/s on 1 thread, {:.1} GB/s on {threads}",
            one / 1e9,
            every / 1e9
        );
        let one = stream::pulls_per_second(one_pool);
        let every = stream::pulls_per_second(all_pool);
        let _ = write!(
            header,
            "\nspring arithmetic (the pull alone, data in cache): {one:.2e} springs/s on 1 thread, {every:.2e} on {threads}"
        );
    }
    (header, triad)
}

/// Build `case` and time it on `pool`'s threads: a warm-up step or two
/// (sizing the buffers, factoring the projective matrix), then at least
/// `steps` steps (or the case's least, if more) and `seconds` of wall
/// clock, or [`LONGEST_SECONDS`] if that comes first. A case that cannot
/// run that long (explicit Euler gains energy until it blows up) starts
/// again from its first state, untimed.
fn time(case: &Case, pool: &parallel::Pool, steps: u32, seconds: f64) -> Result<Row, CliError> {
    let threads = pool.threads();
    let steps = steps.max(case.least_steps);
    pool.install(|| -> Result<Row, CliError> {
        let start_mark = memory::mark();
        let (mut world, dt) = warmed_up(case)?;
        let built_peak = start_mark.peak();
        let stepping = memory::mark();
        let in_use = start_mark.in_use_since();
        let (mut elapsed, mut taken) = (0.0, 0u32);
        let mut allocated: Vec<usize> = Vec::with_capacity(steps as usize + 1024);
        let mut since_restart = 0u32;
        let mut pairs = 0usize;
        let contact = case.group == Group::Contact;
        let give = case.group == Group::Give;
        world.set_profiling(contact || give);
        let longest = seconds.max(LONGEST_SECONDS);
        while taken == 0 || ((taken < steps || elapsed < seconds) && elapsed < longest) {
            let before = memory::allocated();
            let start = Instant::now();
            let result = world.step(dt);
            let took = start.elapsed().as_secs_f64();
            match result {
                // A step that blew up allocates its error message and is
                // not a step of the case: only the steps taken count.
                Ok(_) => {
                    taken += 1;
                    since_restart += 1;
                    elapsed += took;
                    allocated.push(memory::allocated() - before);
                    pairs += world.contacts.candidate_pairs();
                }
                // Blowing up before any step counts (or again at once after
                // a restart) would never end: the case cannot be timed.
                Err(e) if since_restart == 0 => {
                    return Err(CliError::Input(format!("bench, {}: {e}", case.name)))
                }
                Err(_) => {
                    since_restart = 0;
                    // The blown-up world goes before the fresh one is built,
                    // so the peak heap counts one world.
                    drop(world);
                    (world, _) = warmed_up(case)?;
                    world.set_profiling(contact || give);
                }
            }
        }
        let kind = case.integrator;
        Ok(Row {
            group: case.group,
            name: case.name.clone(),
            integrator: kind,
            particles: world.particles.len(),
            springs: world.springs.len(),
            threads,
            dt,
            steps: taken,
            seconds_per_step: elapsed / f64::from(taken),
            evaluations: (!kind.is_implicit() && kind != IntegratorKind::Rk45)
                .then(|| kind.evaluations_per_step()),
            peak_bytes: built_peak.max(start_mark.peak()),
            stepping_bytes: in_use + stepping.peak(),
            allocated_per_step: median(&mut allocated),
            one_thread: 0.0,
            reference: None,
            contact_pairs: contact.then(|| pairs as f64 / f64::from(taken)),
            ccd_share: contact.then(|| world.profile().share(Stage::Ccd)),
            give_share: give.then(|| world.profile().share(Stage::Give)),
            stream_share: None,
        })
    })
}

/// `case`'s world after two untimed steps, and its step (s).
fn warmed_up(case: &Case) -> Result<(sprung::World, Real), CliError> {
    let mut world = (case.build)()?;
    let dt = cases::step_of(case, &world);
    for _ in 0..2 {
        world
            .step(dt)
            .map_err(|e| CliError::Input(format!("bench, {}: {e}", case.name)))?;
    }
    Ok((world, dt))
}

/// `value` in engineering notation, or a dash for none.
fn rate(value: Option<f64>) -> String {
    value.map_or_else(|| "–".into(), |v| format!("{v:.3e}"))
}

fn print_row(row: &Row, header: bool) {
    if header {
        println!(
            "{:<40} {:<16} {:>9} {:>9} {:>3} {:>10} {:>12} {:>12} {:>7} {:>9} {:>8} {:>8} {:>8} {:>9} {:>9} {:>6} {:>6}",
            "case",
            "integrator",
            "particles",
            "springs",
            "thr",
            "ms/step",
            "springs/s",
            "particles/s",
            "speedup",
            "sim s/s",
            "peak MB",
            "run MB",
            "alloc/st",
            "×textbook",
            "pairs/st",
            "stage %",
            "STREAM"
        );
    }
    let textbook = row.reference.map_or_else(
        || "–".into(),
        |r| format!("{:.2}", r / row.seconds_per_step),
    );
    println!(
        "{:<40} {:<16} {:>9} {:>9} {:>3} {:>10.4} {:>12} {:>12.3e} {:>7.2} {:>9.3} {:>8.1} {:>8.1} {:>8} {:>9} {:>9} {:>6} {:>6}",
        row.name,
        row.integrator.name(),
        row.particles,
        row.springs,
        row.threads,
        row.seconds_per_step * 1e3,
        rate(row.spring_updates()),
        row.particle_updates(),
        row.one_thread / row.seconds_per_step,
        row.dt / row.seconds_per_step,
        row.peak_bytes as f64 / 1e6,
        row.stepping_bytes as f64 / 1e6,
        row.allocated_per_step,
        textbook,
        row.contact_pairs
            .map_or_else(|| "–".into(), |p| format!("{p:.0}")),
        row.ccd_share
            .or(row.give_share)
            .map_or_else(|| "–".into(), |s| format!("{:.1}", 100.0 * s)),
        row.stream_share
            .map_or_else(|| "–".into(), |s| format!("{s:.2}"))
    );
}

/// The table as CSV, one row per case and thread count.
fn csv(rows: &[Row]) -> String {
    let mut text = String::from(
        "group,case,integrator,particles,springs,threads,dt,steps,ms_per_step,\
         spring_updates_per_s,particle_updates_per_s,speedup,simulated_s_per_s,\
         peak_bytes,stepping_bytes,bytes_allocated_per_step,textbook_ms_per_step,\
         contact_pairs_per_step,ccd_share,give_share,stream_share\n",
    );
    for row in rows {
        let optional = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:e}"));
        let _ = writeln!(
            text,
            "{},{},{},{},{},{},{:e},{},{:e},{},{:e},{:e},{:e},{},{},{},{},{},{},{},{}",
            row.group.name(),
            row.name,
            row.integrator.name(),
            row.particles,
            row.springs,
            row.threads,
            row.dt,
            row.steps,
            row.seconds_per_step * 1e3,
            optional(row.spring_updates()),
            row.particle_updates(),
            row.one_thread / row.seconds_per_step,
            row.dt / row.seconds_per_step,
            row.peak_bytes,
            row.stepping_bytes,
            row.allocated_per_step,
            optional(row.reference.map(|r| r * 1e3)),
            optional(row.contact_pairs),
            optional(row.ccd_share),
            optional(row.give_share),
            optional(row.stream_share),
        );
    }
    text
}
