//! A force written as a user would, with its stiffness and its energy:
//! the stable-step estimate counts it, and `diagnostics.csv` gives its
//! energy a column of its own, after the standard ones.

use sprung::forces::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use sprung::{BodyData, IntegratorKind, Real, SpringData, Vec3, World};
use sprung_io::export::Diagnostics;

/// A zero-length spring of stiffness `stiffness` (N/m) tying particle
/// `particle` to `anchor` (m).
#[derive(Debug)]
struct Tether {
    particle: usize,
    anchor: Vec3,
    stiffness: Real,
}

impl Force for Tether {
    fn name(&self) -> &'static str {
        "tether"
    }
    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        let i = self.particle;
        force[i] += self.stiffness * (self.anchor - context.position[i]);
    }
    /// `k / m` on its particle's row.
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        let i = self.particle;
        bounds.stiffness[i] += self.stiffness * context.inverse_mass[i];
    }
    fn energy_name(&self) -> Option<&'static str> {
        Some("tether")
    }
    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        let stretch = context.position[self.particle].distance(self.anchor);
        *energy += 0.5 * self.stiffness * stretch * stretch;
    }
    fn linearize(&mut self, _: &ForceContext) -> Linearization {
        Linearization::Exact
    }
    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        out[self.particle] -= scale.position * self.stiffness * p[self.particle];
    }
    fn add_jacobian_diagonal(&self, _: &ForceContext, scale: JacobianScale, diagonal: &mut [Vec3]) {
        diagonal[self.particle] -= Vec3::splat(scale.position * self.stiffness);
    }
}

/// Two particles of 2 kg joined by a spring of 50 N/m, 1 m apart.
fn dumbbell() -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]).with_mass(2.0);
    body.springs = vec![SpringData::between(0, 1)];
    world
        .add_body("dumbbell", body.with_stiffness(50.0))
        .expect("valid body");
    world
}

#[test]
fn a_users_stiff_force_lowers_the_stable_step() {
    // Gershgorin's bound for the spring alone: each row k (1/m + 1/m) =
    // 50 1/s², so Δt = 2 / √50. With a tether of 450 N/m on particle 1,
    // its row grows by 450 / 2 = 225 to 275 1/s²: Δt = 2 / √275. The
    // same additions in the same order: equal to the last bit.
    let mut world = dumbbell();
    assert_eq!(world.stable_time_step(), 2.0 / (50.0 as Real).sqrt());
    world.forces.push(Box::new(Tether {
        particle: 1,
        anchor: Vec3::new(1.0, 0.5, 0.0),
        stiffness: 450.0,
    }));
    assert_eq!(world.stable_time_step(), 2.0 / (275.0 as Real).sqrt());
    // And automatic substeps follow it: a step of 0.5 s is split into
    // ⌈0.5 / (0.9 Δt)⌉.
    world.settings.substeps = sprung::Substeps::Auto;
    let report = world.step(0.5).expect("stable");
    let expected = (0.5 / (0.9 * 2.0 / (275.0 as Real).sqrt())).ceil() as u32;
    assert_eq!(report.substeps, Some(expected));
}

#[test]
fn a_users_force_gets_its_own_energy_column() {
    // The tether stretched by 0.5 m at the start holds ½ k d² = 56.25 J:
    // the header names it after the standard terms, and the first row
    // writes it (and counts it in the total).
    let mut world = dumbbell();
    world.forces.push(Box::new(Tether {
        particle: 1,
        anchor: Vec3::new(1.0, 0.5, 0.0),
        stiffness: 450.0,
    }));
    assert_eq!(world.energies().get("tether"), Some(56.25));
    assert_eq!(world.energies().total(), 56.25);
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("diagnostics.csv");
    let mut diagnostics = Diagnostics::create(&path, &world, &[]).expect("created");
    diagnostics.record(&world).expect("recorded");
    diagnostics.finish().expect("written");
    let text = std::fs::read_to_string(&path).expect("readable");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    assert_eq!(
        header[..11],
        [
            "step",
            "time",
            "kinetic",
            "spring",
            "gravity",
            "gas",
            "total",
            "contact",
            "gravitation",
            "tether",
            "contacts"
        ]
    );
    let row: Vec<&str> = lines.next().expect("a row").split(',').collect();
    assert_eq!(row[9], "56.25");
    assert_eq!(row[6], "56.25");
}
