//! The cases `sprung bench` times: each a world to build, the step to take
//! and the group it belongs to.

use sprung::build::{self, ClothSprings, SurfaceSprings};
use sprung::integrate::Preconditioner;
use sprung::{BodyData, Gas, IntegratorKind, Real, StrainLimits, Vec3, World};

use super::contacts::{self, balls_in_a_box, folded_cloth};
use super::stiff_cloth::{hung_in_plane, light_cloth, stiff_cloth, FRAME};
use crate::error::CliError;

/// The groups of cases, to pick with `--only`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Group {
    /// Square cloths of growing size, symplectic Euler.
    Cloth,
    /// One cloth under every integrator.
    Integrators,
    /// Gas-filled icospheres.
    Gas,
    /// The stiff cloth at the frame rate under the implicit solvers.
    Stiff,
    /// Contact between bodies and self-collision.
    Contact,
    /// The 256² cloth with springs that may break or yield, against the
    /// same cloth without.
    Give,
    /// Issue 51's stiff cloths at the frame rate, each solver at its
    /// defaults: the light drape and the light cloth hung in its plane,
    /// then what projective's substitution reads and the share of the
    /// STREAM bound it reaches.
    Frame,
}

impl Group {
    /// The group's name in the table and the CSV.
    pub fn name(self) -> &'static str {
        match self {
            Group::Cloth => "cloth",
            Group::Integrators => "integrators",
            Group::Gas => "gas",
            Group::Stiff => "stiff",
            Group::Contact => "contact",
            Group::Give => "give",
            Group::Frame => "frame",
        }
    }
}

/// The step a case takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step {
    /// This step (s).
    Fixed(Real),
    /// The world's stable estimate (the explicit reference of the stiff
    /// cloth: within a few % of the true limit there).
    Stable,
    /// Half the stable estimate (a margin any explicit method keeps).
    HalfStable,
}

/// A world to build and time.
pub struct Case {
    /// Its group.
    pub group: Group,
    /// What it is, in a few words.
    pub name: String,
    /// Its integrator.
    pub integrator: IntegratorKind,
    /// Builds the world.
    pub build: Box<dyn Fn() -> Result<World, CliError> + Send + Sync>,
    /// The step it takes.
    pub dt: Step,
    /// Compared with the textbook loop under `--compare`.
    pub compare: bool,
    /// Least steps timed, whatever `--steps` asks (0: none).
    pub least_steps: u32,
}

/// Least steps timed of a contact scene (0.06 s at [`contacts::DT`]): a
/// pile searches for its pairs every 10 to 25 steps (every 10 in its
/// first 60, while the gas throws the balls' surfaces out), and a window
/// of a few tens of steps would count whichever searches fall in it,
/// swinging the contact's cost per step by a factor near 2.
pub const CONTACT_STEPS: u32 = 300;

fn input(e: impl std::fmt::Display) -> CliError {
    CliError::Input(format!("bench: {e}"))
}

/// A `size × size` cloth, 1 m square, with the builder's default springs
/// (structural, shear, bending), 1 kg, 1000 N/m, hanging from two corners.
pub fn cloth(size: usize, kind: IntegratorKind) -> Result<World, CliError> {
    let mut world = World::new(kind);
    world.add_body("cloth", cloth_body(size)?).map_err(input)?;
    Ok(world)
}

/// The body of [`cloth`].
fn cloth_body(size: usize) -> Result<BodyData, CliError> {
    Ok(build::cloth(size, size, 1.0, 1.0, ClothSprings::default())
        .map_err(|e| CliError::Input(format!("cloth {size}: {e}")))?
        .with_total_mass(1.0)
        .with_stiffness(1000.0)
        .with_damping(0.01)
        .with_pinned(vec![(size - 1) * size, size * size - 1]))
}

/// The [`cloth`] of `size × size` particles under symplectic Euler, its
/// particles numbered at random (a fixed shuffle).
fn shuffled_cloth(size: usize) -> Result<World, CliError> {
    let body = cloth_body(size)?;
    let mut number: Vec<usize> = (0..size * size).collect();
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    for k in (1..number.len()).rev() {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        number.swap(k, (state % (k as u64 + 1)) as usize);
    }
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world
        .add_body("cloth", body.renumbered(&number).map_err(input)?)
        .map_err(input)?;
    Ok(world)
}

/// A gas-filled icosphere of `subdivisions` (642 vertices at 3, 10 242 at
/// 5) in free space: springs on every edge and across every pair of
/// triangles, pressure from the exact volume.
fn gas_ball(subdivisions: usize) -> Result<World, CliError> {
    let mut ball = build::icosphere(1.0, subdivisions, SurfaceSprings::default())
        .map_err(input)?
        .with_total_mass(1.0)
        .with_stiffness(1000.0)
        .with_damping(0.01);
    ball.gas = Some(Gas::new(100.0, 0.0));
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world.add_body("ball", ball).map_err(input)?;
    Ok(world)
}

/// The cases of `groups`: cloths of `sizes`, every integrator on a cloth
/// of `integrators_size`; `quick` takes small ones (to check the bench
/// runs, not to measure).
pub fn cases(groups: &[Group], sizes: &[usize], integrators_size: usize, quick: bool) -> Vec<Case> {
    let mut cases = Vec::new();
    let wanted = |g: Group| groups.is_empty() || groups.contains(&g);
    if wanted(Group::Cloth) {
        for &size in sizes {
            cases.push(Case {
                group: Group::Cloth,
                name: format!("cloth {size}²"),
                integrator: IntegratorKind::SymplecticEuler,
                build: Box::new(move || cloth(size, IntegratorKind::SymplecticEuler)),
                dt: Step::HalfStable,
                compare: true,
                least_steps: 0,
            });
        }
        // The memory claim: the largest cloth under RK4 (five state-sized
        // buffers besides the state).
        let largest = sizes.iter().copied().max().unwrap_or(0);
        if largest > 0 {
            cases.push(Case {
                group: Group::Cloth,
                name: format!("cloth {largest}²"),
                integrator: IntegratorKind::Rk4,
                build: Box::new(move || cloth(largest, IntegratorKind::Rk4)),
                dt: Step::HalfStable,
                compare: false,
                least_steps: 0,
            });
        }
        // A cloth as a mesh file may number it: its vertices in no order
        // along it (the engine reads its springs in a numbering of its own).
        let size = if quick { 100 } else { 160 };
        cases.push(Case {
            group: Group::Cloth,
            name: format!("cloth {size}² numbered at random"),
            integrator: IntegratorKind::SymplecticEuler,
            build: Box::new(move || shuffled_cloth(size)),
            dt: Step::HalfStable,
            compare: false,
            least_steps: 0,
        });
    }
    if wanted(Group::Integrators) {
        for kind in IntegratorKind::ALL {
            let size = integrators_size;
            cases.push(Case {
                group: Group::Integrators,
                name: format!("cloth {size}²"),
                integrator: kind,
                build: Box::new(move || cloth(size, kind)),
                dt: Step::HalfStable,
                compare: false,
                least_steps: 0,
            });
        }
    }
    if wanted(Group::Gas) {
        for subdivisions in if quick { vec![2] } else { vec![3, 5] } {
            cases.push(Case {
                group: Group::Gas,
                name: format!("gas ball ({subdivisions} subdivisions)"),
                integrator: IntegratorKind::SymplecticEuler,
                build: Box::new(move || gas_ball(subdivisions)),
                dt: Step::HalfStable,
                compare: false,
                least_steps: 0,
            });
        }
    }
    if wanted(Group::Stiff) {
        for size in if quick { vec![16] } else { vec![64, 128] } {
            for (kind, preconditioner, dt) in [
                (
                    IntegratorKind::SymplecticEuler,
                    Preconditioner::Auto,
                    Step::Stable,
                ),
                (
                    IntegratorKind::ImplicitEuler,
                    Preconditioner::Auto,
                    Step::Fixed(FRAME),
                ),
                (
                    IntegratorKind::ImplicitEuler,
                    Preconditioner::Jacobi,
                    Step::Fixed(FRAME),
                ),
                (
                    IntegratorKind::ImplicitEuler,
                    Preconditioner::Laplacian,
                    Step::Fixed(FRAME),
                ),
                (
                    IntegratorKind::Projective,
                    Preconditioner::Auto,
                    Step::Fixed(FRAME),
                ),
            ] {
                // The default (auto) unnamed; the others named.
                let pc = match (kind, preconditioner) {
                    (IntegratorKind::ImplicitEuler, Preconditioner::Jacobi) => " (Jacobi pc.)",
                    (_, Preconditioner::Laplacian) => " (Laplacian pc.)",
                    _ => "",
                };
                cases.push(Case {
                    group: Group::Stiff,
                    name: format!("stiff cloth {size}²{pc}"),
                    integrator: kind,
                    build: Box::new(move || {
                        let mut world = stiff_cloth(size, kind)?;
                        world.settings.solver.preconditioner = preconditioner;
                        Ok(world)
                    }),
                    dt,
                    compare: false,
                    least_steps: 0,
                });
            }
        }
    }
    if wanted(Group::Contact) {
        let counts = if quick { vec![4] } else { vec![10, 100, 1000] };
        for count in counts {
            for on in [true, false] {
                let label = if on { "" } else { " (contact off)" };
                cases.push(Case {
                    group: Group::Contact,
                    name: format!("{count} gas balls in a box{label}"),
                    integrator: IntegratorKind::SymplecticEuler,
                    build: Box::new(move || balls_in_a_box(count, on)),
                    dt: Step::Fixed(contacts::DT),
                    compare: false,
                    least_steps: if quick { 0 } else { CONTACT_STEPS },
                });
            }
        }
        let size = if quick { 16 } else { 128 };
        for on in [true, false] {
            let label = if on { "" } else { " (contact off)" };
            cases.push(Case {
                group: Group::Contact,
                name: format!("folded cloth {size}² self-colliding{label}"),
                integrator: IntegratorKind::SymplecticEuler,
                build: Box::new(move || folded_cloth(size, on)),
                // The 128² cloth's springs (1 kg on 2 m) are stable below
                // 7e-5 s, whatever the contacts.
                dt: Step::HalfStable,
                compare: false,
                least_steps: if quick { 0 } else { CONTACT_STEPS },
            });
        }
    }
    if wanted(Group::Give) {
        // Limits far above the hanging cloth's strains (a few %): the cost
        // of watching them, none of giving.
        let size = if quick { 32 } else { 256 };
        let limits = [
            ("", StrainLimits::default()),
            (
                " with break_strain",
                StrainLimits {
                    break_strain: Some(10.0),
                    ..StrainLimits::default()
                },
            ),
            (
                " with yield_strain",
                StrainLimits {
                    yield_strain: Some(5.0),
                    hardening: 0.1,
                    ..StrainLimits::default()
                },
            ),
        ];
        for (label, limits) in limits {
            cases.push(Case {
                group: Group::Give,
                name: format!("cloth {size}²{label}"),
                integrator: IntegratorKind::SymplecticEuler,
                build: Box::new(move || {
                    let mut body = cloth_body(size)?;
                    body.limits = limits;
                    let mut world = World::new(IntegratorKind::SymplecticEuler);
                    world.add_body("cloth", body).map_err(input)?;
                    Ok(world)
                }),
                dt: Step::HalfStable,
                compare: false,
                least_steps: 0,
            });
        }
    }
    if wanted(Group::Frame) {
        let (implicit, projective) = (IntegratorKind::ImplicitEuler, IntegratorKind::Projective);
        for &size in frame_sizes(quick) {
            // Implicit Euler's 256² factorisation alone takes seconds.
            let kinds: &[IntegratorKind] = match size {
                256 => &[projective],
                _ => &[projective, implicit],
            };
            for &kind in kinds {
                for hung in [false, true] {
                    cases.push(Case {
                        group: Group::Frame,
                        name: format!("{} {size}²", if hung { "hung" } else { "drape" }),
                        integrator: kind,
                        build: Box::new(move || match hung {
                            true => hung_in_plane(size, kind),
                            false => light_cloth(size, kind, Preconditioner::Auto),
                        }),
                        dt: Step::Fixed(FRAME),
                        compare: false,
                        least_steps: 0,
                    });
                }
            }
        }
    }
    cases
}

/// The sizes of [`Group::Frame`]'s cloths timed under `projective`.
pub fn frame_sizes(quick: bool) -> &'static [usize] {
    if quick {
        &[16]
    } else {
        &[32, 64, 128, 256]
    }
}

/// The step of `case` for `world` (s).
pub fn step_of(case: &Case, world: &World) -> Real {
    match case.dt {
        Step::Fixed(dt) => dt,
        Step::Stable => world.stable_time_step(),
        Step::HalfStable => 0.5 * world.stable_time_step(),
    }
}
